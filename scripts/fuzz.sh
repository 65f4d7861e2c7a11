#!/usr/bin/env bash
# Builds the libFuzzer targets (clang-14, ASan+UBSan) in build-fuzz/ and runs
# each one on a working corpus seeded from the minimized corpora kept in the
# tree (fuzz/corpus/TARGET), the seeds (fuzz/seeds/, data/) and the crash
# inputs (fuzz/regressions/).  New crash inputs land in fuzz-corpus-work/crashes/.
#   ./scripts/fuzz.sh              short run (CI): 6 s per target
#   ./scripts/fuzz.sh 3600         an hour per target
#   NEARCAP_FUZZ_RUNS=10000000 ./scripts/fuzz.sh 0
#                                  until 10 million executions per target (a campaign)
#   NEARCAP_FUZZ_TARGETS="scene pipeline" ./scripts/fuzz.sh 60   some targets only
#   NEARCAP_FUZZ_BIN=DIR ./scripts/fuzz.sh 60   prebuilt fuzz_* binaries from DIR, no build
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-6}
runs=${NEARCAP_FUZZ_RUNS:-0}
targets=${NEARCAP_FUZZ_TARGETS:-"scene pipeline off obj ply stl pgm csv policy"}
bin=${NEARCAP_FUZZ_BIN:-build-fuzz/fuzz}
if [ -z "${NEARCAP_FUZZ_BIN:-}" ]; then
  # -O1 -g1 (line tables only): crash stacks keep their lines.
  cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DNEARCAP_FUZZ=ON -DNEARCAP_BUILD_TESTS=OFF -DNEARCAP_BUILD_BENCHMARKS=OFF >/dev/null
  cmake --build build-fuzz --target $(for t in $targets; do printf 'fuzz_%s ' "$t"; done)
fi
work=fuzz-corpus-work
mkdir -p "$work/crashes"
status=0
for target in $targets; do
  corpus="$work/$target"
  mkdir -p "$corpus"
  case $target in
    scene) find data/scenes fuzz/seeds/scene -name '*.json' -size -64k -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    pipeline) find fuzz/seeds/pipeline -name '*.json' -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    pgm) find fuzz/seeds/pgm -name '*.pgm' -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    csv) find fuzz/seeds/csv -name '*.csv' -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    policy) find fuzz/seeds/policy -name '*.json' -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
    *) find data/meshes tests/data fuzz/seeds/$target -name "*.$target" -size -64k -exec cp {} "$corpus/" \; 2>/dev/null || true ;;
  esac
  for kept in fuzz/corpus/$target fuzz/regressions/$target; do
    [ -d "$kept" ] && cp "$kept"/* "$corpus/" 2>/dev/null || true
  done
  log="$work/$target.log"
  limits=(-max_total_time="$seconds")
  [ "$runs" != "0" ] && limits=(-runs="$runs")
  max_len=65536
  case $target in pipeline | csv) max_len=16384 ;; esac
  start=$(date +%s)
  if "$bin/fuzz_$target" "$corpus" "${limits[@]}" -max_len=$max_len -rss_limit_mb=2048 -timeout=60 \
       -artifact_prefix="$work/crashes/$target-" -print_final_stats=1 >"$log" 2>&1; then
    executed=$(grep -E "stat::number_of_executed_units" "$log" | awk '{print $2}')
    echo "fuzz_$target: ${executed:-?} executions in $(( $(date +%s) - start )) s, no crash"
  else
    echo "fuzz_$target: CRASH, see $log and $work/crashes/"
    tail -30 "$log"
    status=1
  fi
done
exit $status
