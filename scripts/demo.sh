#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine: installs the packages, builds,
# then
#   1. runs every command on data/scenes/near_cap_bunny_wall.json (the Stanford
#      bunny between a light and the camera's near plane, a wall behind: where
#      ZP+ as published cracks and its corrections do not), results under
#      out/near_cap_bunny_wall/, the real GL's lit frames (headless EGL) in
#      out/near_cap_bunny_wall/render/;
#   2. sweeps the bundled camera paths (data/paths/, 430 frames at 160 x 120)
#      and 200 hard configurations of the sampler through the exact reference
#      and the five float methods, with the engines' Z-pass / Z-fail rules
#      (Doom 3, Doom 3 BFG, Ogre, always Z-fail) and the shipped switch policy
#      (data/policy.json) beside them (out/sweep/rows.csv);
#   3. tunes a switch policy on the same configurations (ZP+ with the
#      clipped-sides near-cap and Z-fail, both with the infinite far plane,
#      out/sweep/tuning.csv), as analysis/tuning/tune_policy.sh tunes the
#      shipped one, prints how it classifies them, calibrates its device
#      profile on the real GL (40 configurations of seed 1 and the bundled
#      paths but near_plane_sweep and fly_around) and fits the frames its
#      decision should not price (the same 40): out/sweep/policy.json; then
#      judges it against the oracle and the fixed rules end to end on data
#      its profile was not fitted on (40 configurations of seed 4242 and
#      near_plane_sweep's frames 40-59) and prints the table:
#      out/sweep/oracle/table.md;
#   4. writes the report, with that policy's fitted models:
#      out/sweep/report/index.html;
#   5. compares the l_near rules and P_l formulations on 300 hard cases where
#      they matter (one series per variant): out/sweep/variants/index.html.
# Run again, it continues the
# sweep where it stopped (--resume; a CSV from other options or an older
# nearcap is set aside as rows.csv.old) and rewrites the report.
# Another scene for part 1: ./scripts/demo.sh data/scenes/NAME.json
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
scene=${1:-data/scenes/near_cap_bunny_wall.json}
out=out/$(basename "$scene" .json)
mkdir -p "$out"
echo "== nearcap classify $scene"
./build/nearcap classify "$scene"
./build/nearcap classify "$scene" --json > "$out/classify.json"
echo "== nearcap cap $scene --light 0 (the exact near-cap; picture: $out/cap.svg)"
./build/nearcap cap "$scene" --light 0 --out "$out/cap.json" --svg "$out/cap.svg"
echo "== nearcap reference $scene --light 0 (the exact per-pixel counts; picture: $out/shadow.png)"
./build/nearcap reference "$scene" --light 0 --out "$out" >/dev/null
echo "== nearcap cracks $scene --light 0 --table (every float method against the exact reference)"
./build/nearcap cracks "$scene" --light 0 --table --out "$out"
echo "== nearcap render $scene --out $out/render (the real GL, headless: lit frames; and against the emulation)"
if ./build/nearcap render "$scene" --method zpass,zfail,zpplus-corrected,policy --out "$out/render" >/dev/null; then
  ./build/nearcap render "$scene" --light 0 --compare --table --method zpass,zfail,zpplus-corrected,policy
else
  echo "   (no headless OpenGL on this machine: the real-GL part is skipped; the rest does not need it)"
fi
echo "== results in $out/: cracks-METHOD.png shows each method's wrong pixels, ringed, with a legend;"
echo "   render/frame-METHOD.png the real GL's lit frames"
ls -l "$out"

echo "== nearcap sweep: the bundled camera paths and 200 hard configurations (out/sweep/rows.csv)"
mkdir -p out/sweep
resume=()
paths=()
for p in data/paths/*.json; do paths+=(--path "$p"); done
sweep=(./build/nearcap sweep "${paths[@]}" --samples 200 --seed 1 --policies all --out out/sweep/rows.csv)
if [ -e out/sweep/rows.csv ]; then
  # --repair: a run stopped inside a write leaves its last configuration cut
  # off (docs/sweep-files.md).
  resume=(--resume --repair)
  # Only a sweep of these same options (and this nearcap's columns, with its
  # sidecar rows.csv.meta.json) resumes.
  probe=$(mktemp -d)
  ./build/nearcap sweep --samples 1 --width 2 --height 2 --out "$probe/header.csv" >/dev/null 2>&1
  if [ "$(head -1 out/sweep/rows.csv)" != "$(head -1 "$probe/header.csv")" ] ||
    [ ! -e out/sweep/rows.csv.meta.json ]; then
    mv out/sweep/rows.csv out/sweep/rows.csv.old
    resume=()
  fi
  rm -rf "$probe"
fi
if [ ${#resume[@]} -eq 0 ]; then
  "${sweep[@]}"
else
  # A sweep of other option values (another policy file, say) is not
  # resumed: nearcap refuses it, naming the option; it is set aside and the
  # sweep runs again from the start.
  refusal=$(mktemp)
  if ! "${sweep[@]}" "${resume[@]}" 2>&1 | tee "$refusal"; then
    if ! grep -q "cannot resume it with these options" "$refusal"; then
      rm -f "$refusal"
      exit 1
    fi
    echo "   (out/sweep/rows.csv was swept with other options: set aside as rows.csv.old, sweeping again)"
    mv out/sweep/rows.csv out/sweep/rows.csv.old
    mv out/sweep/rows.csv.meta.json out/sweep/rows.csv.old.meta.json
    "${sweep[@]}"
  fi
  rm -f "$refusal"
fi
echo "== nearcap tune: a switch policy fitted on these configurations (out/sweep/tuned.json)"
rm -f out/sweep/tuning.csv
./build/nearcap sweep "${paths[@]}" --samples 200 --seed 1 --methods zpplus,zfail \
  --light-projection clipped-sides --zpass-far infinite --out out/sweep/tuning.csv >/dev/null
./build/nearcap tune out/sweep/tuning.csv --out out/sweep/tuned.json --capped zpplus \
  --variant light-projection=clipped-sides,zpass-far=infinite --light-projection clipped-sides --no-exact-zpass \
  --features none
calibration=()
for p in data/paths/*.json; do
  case $(basename "$p" .json) in near_plane_sweep | fly_around) ;; *) calibration+=(--path "$p") ;; esac
done
if ./build/nearcap calibrate --samples 40 --seed 1 "${calibration[@]}" --out out/sweep/calibration.csv \
  --policy out/sweep/tuned.json --write-policy out/sweep/calibrated.json --no-atomiczp; then
  echo "== nearcap evaluate --fit-unpriced: the frames its decision should not price, fitted on the same 40 (out/sweep/policy.json)"
  ./build/nearcap evaluate --policy out/sweep/calibrated.json --samples 40 --seed 1 --repeats 2 \
    --out out/sweep/unpriced --fit-unpriced out/sweep/policy.json | tail -2
  echo "== nearcap evaluate: that policy against the oracle on data it was not tuned on (out/sweep/oracle/table.md)"
  ./build/nearcap evaluate --policy out/sweep/policy.json --samples 40 --seed 4242 \
    --path data/paths/near_plane_sweep.json --first-frame 40 --last-frame 59 --repeats 2 --out out/sweep/oracle
else
  echo "   (no headless OpenGL: the policy keeps no device profile and is not timed against the oracle)"
  cp out/sweep/tuned.json out/sweep/policy.json
fi
echo "== nearcap report out/sweep/rows.csv --out out/sweep/report --policy out/sweep/policy.json"
./build/nearcap report out/sweep/rows.csv --out out/sweep/report --policy out/sweep/policy.json
echo "== nearcap sweep --variant ...: the l_near rules and P_l formulations (out/sweep/variants/index.html)"
rm -f out/sweep/variants.csv
./build/nearcap sweep --samples 300 --seed 5 \
  --kinds light-near-plane,straddling,several-occluders,eye-in-shadow,tiny-near \
  --methods zpplus,zpplus-corrected,zfail --switch-clamp clamp-far \
  --variant l-near=exact-max --variant l-near=near-clamp --variant l-near-scale=0.5 \
  --variant light-projection=composed --variant light-projection=rebased \
  --variant light-projection=clipped-sides,zpass-far=infinite \
  --out out/sweep/variants.csv >/dev/null
./build/nearcap report out/sweep/variants.csv --out out/sweep/variants
echo "== open out/sweep/report/index.html: speed against error, the paths, cracks against conditioning,"
echo "   the engines' rules and the policy; out/sweep/variants/index.html: l_near and P_l compared"
