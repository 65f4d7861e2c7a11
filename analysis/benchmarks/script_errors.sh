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
quietly() {  # COMMAND [ARG...]: runs it with its output dropped (fail_from
  # its stderr where it fails: nearcap's error line is its last line there,
  # while its buffered stdout could come after it)
  quietly_log=$("$@" 2>&1 >/dev/null) || fail_from $? "$1" "$quietly_log"
}
fail_from() {  # STATUS COMMAND STDERR: a command that failed, in fail()'s
  # form from the last line of its stderr: nearcap's own error line keeps its
  # kind and message; any other failure is "unavailable", naming the command
  fail_from_last=$(printf '%s\n' "$3" | tail -n 1)
  case $fail_from_last in
    "nearcap: error ("*"): "*)
      fail_from_kind=${fail_from_last#nearcap: error (}
      fail_from_kind=${fail_from_kind%%)*}
      fail "$fail_from_kind" "${fail_from_last#"nearcap: error ($fail_from_kind): "}"
      ;;
    "") fail unavailable "$2 failed (exit status $1), printing nothing on stderr" ;;
    *) fail unavailable "$2 failed (exit status $1): $fail_from_last" ;;
  esac
}
