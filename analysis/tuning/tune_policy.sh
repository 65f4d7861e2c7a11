#!/usr/bin/env bash
# The shipped switch policy's full tuning run: data/policy.json.
#   1. a sweep of 20,000 hard cases of the sampler (seed 100, 48 x 36) and of
#      every bundled camera path (160 x 120) with ZP+ and Z-fail, ZP+ with the
#      clipped-sides near-cap (no light frustum, README "P_l formulations")
#      and, like Z-fail, the infinite far plane;
#   2. nearcap tune on both, with the four features that need no pass over the
#      geometry (the decision stays O(1) per occluder beyond the pyramid
#      test), on the configurations not held out (README "The switch
#      policy"), checked on those that are.  Where ZP+ never cracks more than
#      Z-fail in training there is nothing to fit, and the policy has no
#      crack model; nor an exact Z-pass test (--no-exact-zpass): ZP+ with this
#      cap is Z-pass, fragment for fragment, wherever the near-cap is empty
#      in the viewport, and right where that test's float Z-pass is not.
# About a minute on 2 cores.  Usage: analysis/tuning/tune_policy.sh [BUILD_DIR] [OUT]
#   (default: build, data/policy.json; the sweeps go to out/tuning/)
set -euo pipefail
cd "$(dirname "$0")/../.."
n=${1:-build}/nearcap
policy=${2:-data/policy.json}
mkdir -p out/tuning
rm -f out/tuning/samples.csv out/tuning/paths.csv
paths=()
for p in data/paths/*.json; do paths+=(--path "$p"); done
choices=(--light-projection clipped-sides --zpass-far infinite)
"$n" sweep --samples 20000 --seed 100 --methods zpplus,zfail "${choices[@]}" --out out/tuning/samples.csv
"$n" sweep "${paths[@]}" --methods zpplus,zfail "${choices[@]}" --out out/tuning/paths.csv
"$n" tune out/tuning/samples.csv out/tuning/paths.csv --out "$policy" --capped zpplus \
  --variant light-projection=clipped-sides,zpass-far=infinite \
  --light-projection clipped-sides --no-exact-zpass \
  --features log_light_near_distance,log_l_far_over_width,log_delta_over_width,log_skew
