#!/usr/bin/env bash
# The float ray tracer (Embree) on every bundled scene with each shadow
# epsilon, judged against the exact reference: the table of
# docs/findings/raytrace.md.  Cells: wrong / cracks
# (wrong-lit, wrong-shadowed).  Needs a build (./scripts/build.sh) with Embree.
#   ./analysis/benchmarks/raytrace_table.sh
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=./build/nearcap
need_nearcap "$n"
echo "| scene | seen | fixed | relative | primitive-id | Z-fail |"
echo "|---|---:|---:|---:|---:|---:|"
for scene in data/scenes/*.json; do
  cells=""
  seen=""
  for e in fixed relative primitive-id; do
    cell=$($n cracks "$scene" --light 0 --method raytrace,zfail --shadow-epsilon "$e" | /usr/bin/python3 -c '
import json, sys
records = {r["method"]: r for r in json.load(sys.stdin)["methods"]}
r, z = records["raytrace"], records["zfail"]
print(r["pixels_seen"], "%d / %d (%d, %d)" % (r["wrong"], r["cracks"], r["wrong_lit"], r["wrong_shadowed"]),
      "%d / %d" % (z["wrong"], z["cracks"]), sep="\t")')
    seen=$(cut -f1 <<<"$cell")
    cells="$cells | $(cut -f2 <<<"$cell")"
    zfail=$(cut -f3 <<<"$cell")
  done
  echo "| $(basename "$scene" .json) | $seen$cells | $zfail |"
done
