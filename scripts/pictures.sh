#!/usr/bin/env bash
# Regenerates the pictures of the README and docs/ (data/pictures/*.png) from bundled scenes
# and a small sweep (its report's figures):
# runs nearcap on them into out/pictures-work/, then draws the PNGs with
# matplotlib (analysis/pictures/readme_pictures.py; Debian's /usr/bin/python3, where
# python3-matplotlib is).  Needs a build (./scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
. analysis/benchmarks/script_errors.sh  # quietly: a failing command's own error line
n=./build/nearcap
work=out/pictures-work
rm -rf "$work"
mkdir -p "$work"
$n reference data/scenes/near_cap_bunny_silhouettes.json --light 0 --out "$work/bunny_silhouettes" >/dev/null
$n reference data/scenes/near_cap_bunny_wall.json --light 0 --out "$work/bunny_wall_reference" >/dev/null
$n cracks data/scenes/near_cap_bunny_wall.json --light 0 --method zpplus --out "$work/bunny_wall_zpplus" >/dev/null
$n cracks data/scenes/case_d.json --light 0 --method zpplus-corrected --out "$work/case_d_corrected" >/dev/null
$n cracks data/scenes/far_grazing.json --light 0 --method raytrace --out "$work/far_grazing_raytrace" >/dev/null
/usr/bin/python3 analysis/pictures/readme_pictures.py "$work" data/pictures
# The real GL's lit frames (llvmpipe through headless EGL) of Z-pass and Z-fail.
$n render data/scenes/near_cap_bunny_wall.json --method zpass,zfail --out "$work/render" >/dev/null
cp "$work/render/frame-zpass.png" data/pictures/render_zpass.png
cp "$work/render/frame-zfail.png" data/pictures/render_zfail.png
# The README's first picture: the same frame under Z-pass and Z-fail on the real
# GL beside the exact reference, the wrong pixels outlined
# (analysis/pictures/hero_picture.py).
$n render data/scenes/near_cap_bunny_wall.json --light 0 --method zpass,zfail --stencil \
  --out "$work/hero/render" >/dev/null
$n reference data/scenes/near_cap_bunny_wall.json --light 0 --out "$work/hero/reference" >/dev/null
/usr/bin/python3 analysis/pictures/hero_picture.py "$work/hero" data/pictures/hero.png near_cap_bunny_wall
# The sweep report's figures: the near-plane sweep path and 100 hard cases.
quietly $n sweep --path data/paths/near_plane_sweep.json --samples 100 --seed 1 --out "$work/sweep.csv"
$n report "$work/sweep.csv" --out "$work/report" >/dev/null
cp "$work/report/path_near_plane_sweep.png" data/pictures/report_near_plane_sweep.png
cp "$work/report/pareto.png" data/pictures/report_pareto.png
# The viewer (nearcap view under Xvfb): case D's depth-clamp switch on the
# real GL, and the shipped policy, each with its crack overlay.
view_case_d() { xvfb-run -a -s '-screen 0 1280x720x24' $n view data/scenes/case_d.json --method zpplus-corrected,policy "$@"; }
quietly view_case_d --keys 'c wait' --screenshot data/pictures/view_case_d_corrected.png
quietly view_case_d --keys 'm c wait' --screenshot data/pictures/view_case_d_policy.png
# The real GL's per-frame times along the near-plane sweep, relative to Z-pass.
quietly $n render --path data/paths/near_plane_sweep.json --method zpass,zfail,zpplus-corrected,policy --bench \
  --out "$work/bench"
cp "$work/bench/bench.png" data/pictures/render_bench_near_plane_sweep.png
