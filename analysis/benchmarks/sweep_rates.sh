#!/usr/bin/env bash
# Configurations per second of `nearcap sweep` (all six methods and the exact
# reference, crack distance and conditioning features included) on the
# issue's target workloads, one run each, on this machine's cores:
#   room + torus paths at 160x120 and at 640x480, the 75k-triangle bunny orbit
#   at 160x120, and 200 hard cases of the sampler at 160x120.
# Usage: analysis/benchmarks/sweep_rates.sh [BUILD_DIR]   (default: build)
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
n=${1:-build}/nearcap
need_nearcap "$n"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rate() {  # label, then the sweep's arguments
  local label=$1
  shift
  local out line
  out=$("$n" sweep "$@" --out "$work/rows.csv" 2>"$work/err.txt") || fail_from $? "$n sweep" "$(cat "$work/err.txt")"
  line=$(printf '%s\n' "$out" | tail -1)
  rm -f "$work/rows.csv"
  printf '%-44s %s\n' "$label" "${line#sweep: }"
}
rate "room paths (fly_around, looking_at) 160x120" --path data/paths/fly_around.json --path data/paths/looking_at.json --width 160 --height 120
rate "room paths (fly_around, looking_at) 640x480" --path data/paths/fly_around.json --path data/paths/looking_at.json --width 640 --height 480
rate "bunny orbit 160x120" --path data/paths/bunny_orbit.json --width 160 --height 120
rate "sampler, 200 hard cases, 160x120" --samples 200 --seed 1 --width 160 --height 120
