#!/usr/bin/env bash
# The bunny orbit's rate (`nearcap sweep --path data/paths/bunny_orbit.json
# --width 160 --height 120`, its closing configurations per second) of two
# builds run alternately, PAIRS pairs, the order swapped from one pair to the
# next: a speed ratio that the machine's speed of the moment, which moves
# within minutes, shares between the two.  One line per pair (the time, both
# rates, BUILD's over OTHER's), then the ratios' median and range.  Give the
# same folder twice for the noise floor (the build against itself).
# Usage: analysis/benchmarks/orbit_against_build.sh BUILD_DIR OTHER_BUILD_DIR [PAIRS] [SWEEP OPTIONS...]
#        (PAIRS: default 8; the sweep options go to both sweeps, e.g.
#        --methods zpass,zfail)
set -euo pipefail
. "$(dirname "$0")/script_errors.sh"
cd "$(dirname "$0")/../.."
[ $# -ge 2 ] || fail usage "usage: orbit_against_build.sh BUILD_DIR OTHER_BUILD_DIR [PAIRS] [SWEEP OPTIONS...]"
a_dir=$1
b_dir=$2
a=$a_dir/nearcap
b=$b_dir/nearcap
need_nearcap "$a"
need_nearcap "$b"
pairs=${3:-8}
[[ $pairs =~ ^[0-9]{1,6}$ ]] && ((10#$pairs > 0)) || fail usage "PAIRS: '$pairs' is not a positive whole number"
shift $(($# < 3 ? $# : 3))
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rate() {  # PROGRAM: the orbit's closing rate, configurations per second
  local out
  rm -f "$work/rows.csv"
  out=$("$1" sweep --path data/paths/bunny_orbit.json --width 160 --height 120 "${options[@]}" \
    --out "$work/rows.csv" 2> "$work/err.txt") || fail_from $? "$1 sweep" "$(cat "$work/err.txt")"
  out=$(printf '%s\n' "$out" | tail -1)
  [[ $out =~ \(([0-9.]+)\ per\ second\) ]] || fail parse "$1 sweep: no rate in its closing line: $out"
  printf '%s' "${BASH_REMATCH[1]}"
}
options=("$@")
ratios=()
for i in $(seq 1 "$pairs"); do
  if ((i % 2)); then
    ra=$(rate "$a")
    rb=$(rate "$b")
  else
    rb=$(rate "$b")
    ra=$(rate "$a")
  fi
  ratio=$(awk -v x="$ra" -v y="$rb" 'BEGIN { printf "%.3f", x / y }')
  ratios+=("$ratio")
  printf '%s  %s %s /s  %s %s /s  ratio %s\n' "$(date -u +%H:%M:%S)" "$a_dir" "$ra" "$b_dir" "$rb" "$ratio"
done
printf '%s\n' "${ratios[@]}" | sort -g | awk '{ v[NR] = $1 } END {
  m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
  printf "%d pairs: ratio median %.3f, range %.3f-%.3f\n", NR, m, v[1], v[NR] }'
