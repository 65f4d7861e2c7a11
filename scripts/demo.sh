#!/usr/bin/env bash
# The main job, from a fresh Debian 12 machine: installs the packages, builds,
# then runs every command on data/scenes/near_cap_bunny_wall.json (the Stanford
# bunny between a light and the camera's near plane, a wall behind: where ZP+
# as published cracks and its corrections do not) and writes the results under
# out/near_cap_bunny_wall/.  Another scene: ./scripts/demo.sh data/scenes/NAME.json
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
./build/nearcap cracks "$scene" --light 0 --table
./build/nearcap cracks "$scene" --light 0 --out "$out" >/dev/null
echo "== results in $out/: cracks-METHOD.png shows each method's wrong pixels, ringed, with a legend"
ls -l "$out"
