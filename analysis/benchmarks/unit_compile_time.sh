#!/bin/sh
# One translation unit's compile time, alone, with the sanitizer build's own
# command line (build-asan, configured as scripts/test.sh configures it), at
# each optimisation level given (appended to the command line: the last -O
# and -g win).  No compiler cache and no precompiled header (the unit parses
# its own includes); the object goes to a temporary file.
#   analysis/benchmarks/unit_compile_time.sh OBJECT LEVEL...
#   e.g. ... tests/CMakeFiles/nearcap_tests.dir/near_cap_test.cpp.o "-O0 -g0" "-O1 -g1"
# OBJECT as ninja names it (`ninja -C build-asan -t targets all`).  GNU
# date (%N) times it, as on the Debian machines the project builds on.
set -eu
. "$(dirname "$0")/script_errors.sh"
[ $# -ge 2 ] || fail usage "usage: unit_compile_time.sh OBJECT LEVEL..."
[ -d "$(dirname "$0")/../../build-asan" ] || fail usage "no build-asan folder (./scripts/test.sh configures it)"
command -v ninja > /dev/null || fail usage "ninja is not installed (apt-get install ninja-build)"
cd "$(dirname "$0")/../../build-asan"
object=$1
shift
command=$(ninja -t commands "$object" 2> /dev/null | tail -1)
[ -n "$command" ] || fail usage "build-asan has no object $object"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
command=$(printf '%s\n' "$command" | sed "s|^.*ccache ||; s| -Xclang -include-pch -Xclang [^ ]*||; s| -Xclang -include -Xclang [^ ]*||; s| -MD -MT [^ ]* -MF [^ ]*||; s| -o [^ ]*| -o $scratch/unit.o|")
for level in "$@"; do
  start=$(date +%s.%N)
  sh -c "$(printf '%s\n' "$command" | sed "s| -c | $level -c |")"
  end=$(date +%s.%N)
  awk -v o="$object" -v l="$level" -v s="$start" -v e="$end" 'BEGIN { printf "%s\t%s\t%.1f s\n", o, l, e - s }'
done
