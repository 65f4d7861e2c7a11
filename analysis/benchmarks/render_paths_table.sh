#!/usr/bin/env bash
# Every bundled camera path drawn by the real GL (headless EGL: llvmpipe
# here), every method and the shipped policy, with the volumes built by the
# GL's GLSL vertex programs (--vertex-stage glsl, the default) and from the
# emulation's recorded vertices (--vertex-stage recorded): per path Z-pass's
# mean frame time and each method's relative to it, the median over REPEATS
# runs (default 3) of each method's mean.  The tables of
# docs/findings/real-gl.md ("Frame times along the bundled paths").  Needs a build (./scripts/build.sh).
#   REPEATS=3 ./analysis/benchmarks/render_paths_table.sh [OUT_DIR]
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=./build/nearcap
need_nearcap "$n"
out=${1:-$(mktemp -d)}
repeats=${REPEATS:-3}
for stage in glsl recorded; do
  echo
  echo "vertex stage: $stage (median of $repeats runs)"
  echo "| path (frames) | zpass | zfail | zpplus | zpplus-corrected | preload | policy |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  for path in data/paths/*.json; do
    name=$(basename "$path" .json)
    for r in $(seq 1 "$repeats"); do
      quietly $n render --path "$path" --vertex-stage "$stage" --out "$out/$stage/$name/$r"
    done
    /usr/bin/python3 - "$name" "$out/$stage/$name" "$repeats" <<'PY'
import json, statistics, sys
name, root, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = [json.load(open("%s/%d/render.json" % (root, r)))["methods"] for r in range(1, repeats + 1)]
order = [m["method"] for m in runs[0]]
mean = {m: statistics.median(next(x for x in run if x["method"] == m)["mean_ms"] for run in runs) for m in order}
cells = ["%.2f ms" % mean["zpass"]] + ["%.2f×" % (mean[m] / mean["zpass"]) for m in order if m != "zpass"]
print("| %s (%d) | %s |" % (name, len(runs[0][0]["frames"]), " | ".join(cells)))
PY
  done
done
