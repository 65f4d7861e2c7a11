#!/usr/bin/env bash
# Scissor culling of the shadow volumes on the real GL (headless EGL:
# llvmpipe here; llvmpipe has no GL_EXT_depth_bounds_test, so depth bounds
# run in the emulation only): every bundled camera path drawn with --bench
# (a glFinish after each pass), without and with --volume-culling scissor,
# for Z-pass, Z-fail, ZP+ corrected and the shipped policy.  Per path and
# method: the stencil pass's mean time, none -> scissor, the median over
# REPEATS runs (default 3); and the policy's whole frame relative to
# Z-pass's, both with the scissor.  The table of
# docs/findings/volume-culling.md.  Needs a build.
#   REPEATS=3 ./analysis/benchmarks/render_culling_table.sh [OUT_DIR]
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=./build/nearcap
need_nearcap "$n"
out=${1:-$(mktemp -d)}
repeats=${REPEATS:-3}
echo "| path | Z-pass stencil | Z-fail stencil | ZP+ corrected stencil | policy stencil | policy frame / Z-pass (scissor) |"
echo "|---|---:|---:|---:|---:|---:|"
for path in data/paths/*.json; do
  name=$(basename "$path" .json)
  for r in $(seq 1 "$repeats"); do
    for culling in none scissor; do
      quietly $n render --path "$path" --method zpass,zfail,zpplus-corrected,policy --bench --volume-culling "$culling" \
        --out "$out/$culling/$name/$r"
    done
  done
  /usr/bin/python3 - "$name" "$out" "$repeats" <<'PY'
import sys
sys.argv[0] = "render_culling_table.sh"  # the name its errors give
sys.path.insert(0, "analysis/benchmarks")
from bench_runs import median_of_means
name, root, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
plain = median_of_means(root, "none", name, repeats, "stencil_ms")
scissor = median_of_means(root, "scissor", name, repeats, "stencil_ms")
frame = median_of_means(root, "scissor", name, repeats, "ms")
cells = ["%.2f → %.2f ms" % (plain[m], scissor[m]) for m in ("zpass", "zfail", "zpplus-corrected", "policy")]
cells.append("%.2f×" % (frame["policy"] / frame["zpass"]))
print("| %s | %s |" % (name, " | ".join(cells)))
PY
done
