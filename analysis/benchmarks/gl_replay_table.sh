#!/usr/bin/env bash
# The real GL (headless EGL: llvmpipe here) beside the emulation on every
# bundled scene but the two largest: per method, the stencil pixels where GL
# and the emulation differ with the spec's viewport arithmetic / with Mesa's
# (--viewport llvmpipe) / with the whole llvmpipe model (--viewport llvmpipe
# --depth-interpolation llvmpipe --clipper mesa), and the wrong pixels of GL
# and of the emulation against the exact reference.  The table of
# docs/findings/real-gl.md.  Needs a build (./scripts/build.sh).
#   ./analysis/benchmarks/gl_replay_table.sh
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=./build/nearcap
need_nearcap "$n"
methods=(zpass zfail zpplus zpplus-corrected preload policy)
echo "| scene | $(IFS='|'; echo "${methods[*]}" | sed 's/|/ | /g') |"
echo "|---|$(for _ in "${methods[@]}"; do printf -- '---|'; done)"
for scene in data/scenes/*.json; do
  name=$(basename "$scene" .json)
  case "$name" in bunny | armadillo) continue ;; esac
  divide=$($n render "$scene" --light 0 --compare)
  llvmpipe=$($n render "$scene" --light 0 --compare --viewport llvmpipe)
  model=$($n render "$scene" --light 0 --compare --viewport llvmpipe --depth-interpolation llvmpipe --clipper mesa)
  /usr/bin/python3 - "$name" "$divide" "$llvmpipe" "$model" <<'PY'
import json, sys
name = sys.argv[1]
a, b, c = (json.loads(sys.argv[k])["methods"] for k in (2, 3, 4))
cells = []
for x, y, z in zip(a, b, c):
    if "refused" in x:
        cells.append("refused")
        continue
    cells.append("%d / %d / %d (GL %d, emul. %d)" % (x["gl_vs_emulation"], y["gl_vs_emulation"], z["gl_vs_emulation"],
                                                      x["gl_vs_exact"], x["emulation_vs_exact"]))
print("| %s | %s |" % (name, " | ".join(cells)))
PY
done
