#!/usr/bin/env bash
# The paper's vertex layouts on the real GL (headless EGL: llvmpipe here):
# every bundled camera path drawn with --bench (a glFinish after each pass),
# the volumes' sides as independent triangles and as triangle strips along
# the silhouette's chains (--side-strips), Z-pass, Z-fail, ZP+ corrected and
# the shipped policy.  Per path and method: the stencil pass's mean time,
# triangles -> strips, the median over REPEATS runs (default 3); and ZP+
# corrected's and the policy's whole frame relative to Z-pass's with strips.
# The table of docs/findings/real-gl.md ("Vertex layouts").  Needs a build.
#   REPEATS=3 ./analysis/benchmarks/render_layout_table.sh [OUT_DIR]
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=./build/nearcap
need_nearcap "$n"
out=${1:-$(mktemp -d)}
repeats=${REPEATS:-3}
echo "| path | Z-pass stencil | Z-fail stencil | ZP+ corrected stencil | policy stencil | ZP+ corrected frame (strips) | policy frame (strips) |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for path in data/paths/*.json; do
  name=$(basename "$path" .json)
  for r in $(seq 1 "$repeats"); do
    $n render --path "$path" --method zpass,zfail,zpplus-corrected,policy --bench \
      --out "$out/triangles/$name/$r" >/dev/null 2>&1
    $n render --path "$path" --method zpass,zfail,zpplus-corrected,policy --bench --side-strips \
      --out "$out/strips/$name/$r" >/dev/null 2>&1
  done
  /usr/bin/python3 - "$name" "$out" "$repeats" <<'PY'
import csv, statistics, sys
name, root, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
def means(layout, column):
    runs = []
    for r in range(1, repeats + 1):
        per = {}
        with open("%s/%s/%s/%d/bench.csv" % (root, layout, name, r)) as f:
            for row in csv.DictReader(f):
                per.setdefault(row["method"], []).append(float(row[column]))
        runs.append({m: sum(v) / len(v) for m, v in per.items()})
    return {m: statistics.median(run[m] for run in runs) for m in runs[0]}
tri, strip = means("triangles", "stencil_ms"), means("strips", "stencil_ms")
frame = means("strips", "ms")
cells = ["%.2f → %.2f ms" % (tri[m], strip[m]) for m in ("zpass", "zfail", "zpplus-corrected", "policy")]
cells += ["%.2f×" % (frame[m] / frame["zpass"]) for m in ("zpplus-corrected", "policy")]
print("| %s | %s |" % (name, " | ".join(cells)))
PY
done
