#!/usr/bin/env bash
# Instructions that the switch policy's decision executes on a camera path's
# frames, counted by callgrind on one core (only inside
# nearcap::analysis::decide): a measure of the decision's work that does not
# move with the machine's speed of the day.  `nearcap sweep` decides once per
# frame and light, with no facing cache (render and evaluate keep the
# occluders' facing from frame to frame while the light and the occluder
# stay put), ChoiceOnly as a frame loop decides.  Prints the decisions, the
# instructions per decision and the functions under decide with the largest
# inclusive counts.
# Usage: analysis/benchmarks/decision_instructions.sh [BUILD_DIR] [PATH_JSON] [POLICY]
#        (defaults: build, data/paths/near_plane_sweep.json, data/policy.json;
#        valgrind must be installed)
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=${1:-build}/nearcap
need_nearcap "$n"
path=${2:-data/paths/near_plane_sweep.json}
policy=${3:-data/policy.json}
[ -f "$path" ] || fail io "$path: no such path file"
[ -f "$policy" ] || fail io "$policy: no such policy file"
command -v valgrind > /dev/null || fail usage "valgrind is not installed (apt-get install valgrind)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
taskset -c 0 valgrind --tool=callgrind --callgrind-out-file="$work/callgrind.out" \
  --toggle-collect='nearcap::analysis::decide(*' \
  "$n" sweep --path "$path" --methods zfail --policies policy --policy "$policy" --out "$work/rows.csv" \
  2> "$work/valgrind.log" > /dev/null || {
  fail io "the sweep under valgrind failed: $(grep -v "^==" "$work/valgrind.log" | tail -1)"
}
total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$work/valgrind.log")
decisions=$(python3 -c 'import csv,sys; print(sum(r["method"] == "policy" for r in csv.DictReader(open(sys.argv[1]))))' \
  "$work/rows.csv")
[ "$decisions" -gt 0 ] || {
  fail io "the sweep made no decision"
}
printf '%s: %s decisions, %s instructions in decide (%.2f M per decision)\n' "$path" "$decisions" "$total" \
  "$(python3 -c "print($total / $decisions / 1e6)")"
echo "under decide, inclusive (share of decide's instructions):"
callgrind_annotate --inclusive=yes "$work/callgrind.out" 2> /dev/null |
  grep -E '^ *[0-9,]+ +\( *[0-9.]+%\) +\?\?\?:nearcap::' | grep -v 'nearcap::cli::\|sweep_configuration' |
  sed -E 's/\(nearcap::[^)]*\)//; s/ \[.*\]$//' | head -12 || true
