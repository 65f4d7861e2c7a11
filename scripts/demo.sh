#!/usr/bin/env bash
# The main job on the bundled default scene, from a fresh Debian 12 machine:
# installs the packages, builds, then runs the exact kernel on
# data/scenes/default.json and writes its results under out/default/.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
scene=${1:-data/scenes/default.json}
out=out/$(basename "$scene" .json)
mkdir -p "$out"
echo "== nearcap classify $scene"
./build/nearcap classify "$scene"
./build/nearcap classify "$scene" --json > "$out/classify.json"
if ./build/nearcap cap --help >/dev/null 2>&1; then
  echo "== nearcap cap $scene --light 0"
  ./build/nearcap cap "$scene" --light 0 --out "$out/cap.json" --svg "$out/cap.svg"
fi
if ./build/nearcap reference --help >/dev/null 2>&1; then
  echo "== nearcap reference $scene --light 0"
  ./build/nearcap reference "$scene" --light 0 --out "$out"
fi
if ./build/nearcap cracks --help >/dev/null 2>&1; then
  echo "== nearcap cracks $scene --light 0 --table"
  ./build/nearcap cracks "$scene" --light 0 --table
  ./build/nearcap cracks "$scene" --light 0 --out "$out" >/dev/null
fi
echo "== results in $out/"
ls -l "$out"
