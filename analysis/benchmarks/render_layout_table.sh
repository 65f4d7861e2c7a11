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
    quietly $n render --path "$path" --method zpass,zfail,zpplus-corrected,policy --bench \
      --out "$out/triangles/$name/$r"
    quietly $n render --path "$path" --method zpass,zfail,zpplus-corrected,policy --bench --side-strips \
      --out "$out/strips/$name/$r"
  done
  /usr/bin/python3 - "$name" "$out" "$repeats" <<'PY'
import sys
sys.argv[0] = "render_layout_table.sh"  # the name its errors give
sys.path.insert(0, "analysis/benchmarks")
from bench_runs import median_of_means
name, root, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
tri = median_of_means(root, "triangles", name, repeats, "stencil_ms")
strip = median_of_means(root, "strips", name, repeats, "stencil_ms")
frame = median_of_means(root, "strips", name, repeats, "ms")
cells = ["%.2f → %.2f ms" % (tri[m], strip[m]) for m in ("zpass", "zfail", "zpplus-corrected", "policy")]
cells += ["%.2f×" % (frame[m] / frame["zpass"]) for m in ("zpplus-corrected", "policy")]
print("| %s | %s |" % (name, " | ".join(cells)))
PY
done
