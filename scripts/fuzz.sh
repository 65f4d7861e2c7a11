#!/usr/bin/env bash
# Builds the libFuzzer targets (clang-14, ASan+UBSan) in build-fuzz/ and runs
# each for SECONDS seconds (default 12) on a working corpus seeded from data/
# and fuzz/regressions/.  New crash inputs land in fuzz-corpus-work/crashes/.
#   ./scripts/fuzz.sh          short run (CI)
#   ./scripts/fuzz.sh 3600     long run: an hour per target
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-12}
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
  -DNEARCAP_FUZZ=ON -DNEARCAP_BUILD_TESTS=OFF -DNEARCAP_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-fuzz --target fuzz_scene fuzz_off fuzz_obj fuzz_ply fuzz_stl fuzz_pgm
work=fuzz-corpus-work
mkdir -p "$work/crashes"
status=0
for target in scene off obj ply stl pgm; do
  corpus="$work/$target"
  mkdir -p "$corpus"
  case $target in
    scene) find data/scenes fuzz/seeds/scene -name '*.json' -size -64k -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    pgm) find fuzz/seeds/pgm -name '*.pgm' -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    *) find data/meshes tests/data fuzz/seeds/$target -name "*.$target" -size -64k -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
  esac
  regress=fuzz/regressions/$target
  [ -d "$regress" ] && cp "$regress"/* "$corpus/" 2>/dev/null || true
  log="$work/$target.log"
  if ./build-fuzz/fuzz/fuzz_$target "$corpus" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 \
       -artifact_prefix="$work/crashes/$target-" -print_final_stats=1 >"$log" 2>&1; then
    runs=$(grep -E "stat::number_of_executed_units" "$log" | awk '{print $2}')
    echo "fuzz_$target: ${runs:-?} executions in ${seconds}s, no crash"
  else
    echo "fuzz_$target: CRASH, see $log and $work/crashes/"
    tail -30 "$log"
    status=1
  fi
done
exit $status
