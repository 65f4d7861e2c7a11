#!/usr/bin/env bash
# Regenerates the README's pictures (data/pictures/*.png) from bundled scenes:
# runs nearcap on them into out/pictures-work/, then draws the PNGs with
# matplotlib (analysis/pictures/readme_pictures.py; Debian's /usr/bin/python3, where
# python3-matplotlib is).  Needs a build (./scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
n=./build/nearcap
work=out/pictures-work
rm -rf "$work"
mkdir -p "$work"
$n reference data/scenes/near_cap_bunny_silhouettes.json --light 0 --out "$work/bunny_silhouettes" >/dev/null
$n reference data/scenes/near_cap_bunny_wall.json --light 0 --out "$work/bunny_wall_reference" >/dev/null
$n cracks data/scenes/near_cap_bunny_wall.json --light 0 --method zpplus --out "$work/bunny_wall_zpplus" >/dev/null
$n cracks data/scenes/case_d.json --light 0 --method zpplus-corrected --out "$work/case_d_corrected" >/dev/null
/usr/bin/python3 analysis/pictures/readme_pictures.py "$work" data/pictures
