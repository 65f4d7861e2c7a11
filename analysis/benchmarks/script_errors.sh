# Bad input to a benchmark helper script in shell, sourced by it (POSIX sh):
# one line on stderr, exit status 2, "nearcap: error (KIND): SCRIPT: ...", as
# script_errors.py says it for the Python ones.
fail() {  # KIND MESSAGE
  printf '%s\n' "nearcap: error ($1): $(basename "$0"): $(printf '%s' "$2" | tr '\n' ' ')" >&2
  exit 2
}
need_nearcap() {  # PROGRAM: the nearcap a script runs, built
  [ -f "$1" ] && [ -x "$1" ] || fail usage "$1: no such program (build it first: ./scripts/build.sh)"
}
