#!/usr/bin/env bash
# Instructions that `nearcap sweep` executes on the first FRAMES frames of the
# bunny orbit (data/paths/bunny_orbit.json, 160x120, every method, the exact
# reference and crack distances), counted by callgrind on one core: a measure
# of the sweep's work that does not move with the machine's speed of the day.
# Prints callgrind's total and the functions with the largest own counts.
# Usage: analysis/benchmarks/orbit_instructions.sh [BUILD_DIR] [FRAMES]
#        (defaults: build, 6; valgrind must be installed)
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=${1:-build}/nearcap
need_nearcap "$n"
frames=${2:-6}
[[ $frames =~ ^[0-9]{1,9}$ ]] && ((10#$frames > 0)) || fail usage "FRAMES: '$frames' is not a positive whole number"
command -v valgrind > /dev/null || fail usage "valgrind is not installed (apt-get install valgrind)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$frames" "$work/orbit.json" << 'EOF'
import json, os, sys
path = "data/paths/bunny_orbit.json"
orbit = json.load(open(path))
orbit["frames"] = int(sys.argv[1])
orbit["scene"] = os.path.abspath(os.path.join(os.path.dirname(path), orbit["scene"]))
json.dump(orbit, open(sys.argv[2], "w"))
EOF
taskset -c 0 valgrind --tool=callgrind --callgrind-out-file="$work/callgrind.out" \
  "$n" sweep --path "$work/orbit.json" --out "$work/rows.csv" 2> "$work/valgrind.log" > /dev/null
total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$work/valgrind.log")
printf 'bunny orbit, %s frames: %s instructions (%.3f G per frame)\n' "$frames" "$total" \
  "$(python3 -c "print($total / $frames / 1e9)")"
callgrind_annotate "$work/callgrind.out" 2> /dev/null | grep -E '^ *[0-9,]+ \(' | sed -n '2,13p' |
  sed -E 's/ \[[^]]*\]$//; s/\?\?\?://; s/\(anonymous namespace\):://g; s/nearcap:://g' |
  sed -E ':a; s/\(([^()]|\(\))*\)//g; ta' | cut -c1-110
