#!/usr/bin/env bash
# The shipped switch policies' full tuning run: data/policy.json.
#   1. a sweep of 20,000 hard cases of the sampler (seed 100, 48 x 36) and of
#      every bundled camera path (160 x 120) with ZP+ and Z-fail, ZP+ with the
#      clipped-sides near-cap (no light frustum, docs/findings/light-projection.md)
#      and, like Z-fail, the infinite far plane;
#   2. nearcap tune on both, without an exact Z-pass test (--no-exact-zpass):
#      ZP+ with this cap is Z-pass, fragment for fragment, wherever its float
#      sides leave no cap in the viewport, and right where the float Z-pass of
#      an occluder with an exactly empty near-cap is not (nearcap sample
#      --seed 7 --index 638: a box 10^6 from the origin).  Without the test
#      the decision asks no crack model, so none is fitted (--features none;
#      tune refuses to write one its switches bypass); the confusion tables on
#      the configurations not held out and on those that are
#      (docs/findings/policy.md) still count where ZP+ cracks more than Z-fail;
#   3. nearcap calibrate: the device profile on this machine's GL (each pass
#      kind and CPU task timed on its own, fitted with Ceres), on 100 of the
#      sampler's configurations (seed 100) and the bundled paths except
#      near_plane_sweep and fly_around, which `nearcap evaluate` holds out
#      (docs/findings/policy-oracle.md), without AtomicZP's eye-count row
#      (--no-atomiczp: testing AtomicZP's conditions would cost the decision
#      more than the candidate saves, docs/policy.md).  With it the policy
#      decides per occluder by predicted cost between ZP+ with the
#      clipped-sides cap and Z-fail (docs/policy.md).
#      Without headless OpenGL the policy is written without a profile (the
#      clipped-sides ZP+ for every occluder);
#   4. nearcap evaluate --fit-unpriced on 500 configurations of seed 100 at
#      160 x 120: the calibrated policy drawn and timed end to end beside the
#      fixed rules, and the frames its decision should not price fitted
#      (tiers of the largest occluder's triangles up to a threshold, each
#      with the cheaper of Z-fail and the clipped-sides ZP+: where choosing
#      gained less than the pricing's own time; docs/policy.md);
#   5. with --reversed-z: the same with reversed-Z (a float depth buffer and
#      the reversed depth mapping) in the sweeps and the policy:
#      data/policy-reversed-z.json; with --tight-near: the same with the
#      tight near plane, data/policy-tight-near.json (docs/methods.md "Depth
#      precision").  Both without a profile.
# A few minutes on 2 cores.  Usage:
#   analysis/tuning/tune_policy.sh [--reversed-z|--tight-near] [BUILD_DIR] [OUT]
#   (default: build, data/policy.json, data/policy-reversed-z.json or
#   data/policy-tight-near.json; the sweeps go to out/tuning/)
set -euo pipefail
cd "$(dirname "$0")/../.."
cure=none
if [ "${1:-}" = "--reversed-z" ] || [ "${1:-}" = "--tight-near" ]; then
  cure=${1#--}
  shift
fi
n=${1:-build}/nearcap
choices=(--light-projection clipped-sides --zpass-far infinite)
variant=light-projection=clipped-sides,zpass-far=infinite
depth=()
if [ "$cure" = reversed-z ]; then
  policy=${2:-data/policy-reversed-z.json}
  choices+=(--depth float32 --depth-mapping reversed)
  variant=depth=float32,light-projection=clipped-sides,zpass-far=infinite,depth-mapping=reversed
  depth=(--depth float32 --depth-mapping reversed)
  work=out/tuning/reversed-z
elif [ "$cure" = tight-near ]; then
  policy=${2:-data/policy-tight-near.json}
  choices+=(--near-plane tight)
  variant=light-projection=clipped-sides,zpass-far=infinite,near-plane=tight
  depth=(--near-plane tight)
  work=out/tuning/tight-near
else
  policy=${2:-data/policy.json}
  work=out/tuning
fi
mkdir -p "$work"
rm -f "$work/samples.csv" "$work/paths.csv"
paths=()
for p in data/paths/*.json; do paths+=(--path "$p"); done
"$n" sweep --samples 20000 --seed 100 --methods zpplus,zfail "${choices[@]}" --out "$work/samples.csv"
"$n" sweep "${paths[@]}" --methods zpplus,zfail "${choices[@]}" --out "$work/paths.csv"
tuned=$policy
[ "$cure" = none ] && tuned=$work/tuned.json
"$n" tune "$work/samples.csv" "$work/paths.csv" --out "$tuned" --capped zpplus \
  --variant "$variant" \
  --light-projection clipped-sides --no-exact-zpass "${depth[@]}" \
  --features none
if [ "$cure" = none ]; then
  calibration=()
  for p in data/paths/*.json; do
    case $(basename "$p" .json) in near_plane_sweep | fly_around) ;; *) calibration+=(--path "$p") ;; esac
  done
  if ! "$n" calibrate --samples 100 --seed 100 "${calibration[@]}" --width 160 --height 120 \
    --out "$work/calibration.csv" --policy "$tuned" --write-policy "$policy" --no-atomiczp; then
    echo "tune_policy.sh: no device profile (nearcap calibrate failed: no headless OpenGL?); $policy without one"
    cp "$tuned" "$policy"
  else
    cp "$policy" "$work/calibrated.json"
    "$n" evaluate --policy "$work/calibrated.json" --samples 500 --seed 100 --width 160 --height 120 --repeats 8 \
      --out "$work/unpriced" --fit-unpriced "$policy"
  fi
fi
