#!/usr/bin/env bash
# The README's test command, and what CI runs: installs the packages, checks
# formatting, builds with warnings as errors and runs the test suite, then
# builds and runs the suite again under AddressSanitizer + UndefinedBehaviorSanitizer,
# then gives each fuzzer a short run.  Any failure, sanitizer report or crash fails it.
#   NEARCAP_QUICK=1 ./scripts/test.sh   skips the sanitizer build and the fuzzers
set -euo pipefail
cd "$(dirname "$0")/.."
# The suite writes outputs onto FIFOs, symlinks and /proc/self/fd/1; a test
# that renames over such a path run as root could replace /dev/null with a
# regular file, so it is checked before and after.
check_dev_null() {
  if [ ! -c /dev/null ]; then
    echo "test.sh: /dev/null is not a character device; restore it with: rm /dev/null && mknod -m 666 /dev/null c 1 3" >&2
    exit 1
  fi
}
check_dev_null
trap check_dev_null EXIT
# Each stage's wall time, printed as it ends (docs/development.md has a run's).
stage_start=$(date +%s)
stage_done() {
  echo "test.sh: $1 done in $(( $(date +%s) - stage_start )) s"
  stage_start=$(date +%s)
}
./scripts/install-deps.sh
./scripts/check-format.sh
stage_done "packages and format check"
# The tests' own units at -O1: the library they test is the Release build's
# (-O3); their own code compiles faster at -O1.
./scripts/build.sh -DNEARCAP_WERROR=ON -DNEARCAP_BUILD_TESTS=ON -DNEARCAP_TEST_CXX_FLAGS=-O1
stage_done "Release build"
# matplotlib builds its font cache on its first import, and when that takes
# long it says so on stderr, which some tests read whole: build it first,
# with the Python nearcap runs its scripts with (NEARCAP_PYTHON, else
# Debian's, else the first python3 on PATH).
python=${NEARCAP_PYTHON:-/usr/bin/python3}
if [ -z "${NEARCAP_PYTHON:-}" ] && [ ! -x /usr/bin/python3 ]; then python=python3; fi
"$python" -c 'import matplotlib.font_manager'
ctest --test-dir build --output-on-failure --no-tests=error -j2
stage_done "Release suite"
if [ "${NEARCAP_QUICK:-0}" = "1" ]; then exit 0; fi
# clang 14, the fuzzers' compiler: the Release build is GCC's, so the suite
# runs under both, and clang compiles this build in about two thirds of GCC's
# time.  The library at -O2 -g1 (line tables for the reports' stacks): its
# longest tests run in about three quarters of -O1's time, for a fifth more
# build.
# The tests' and the program's own units at -O0 -g0: their work is the
# library's, whose frames keep their lines (docs/findings/ci-time.md).
cmake -S . -B build-asan -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DNEARCAP_DRIVER_CXX_FLAGS='-O0 -g0' -DNEARCAP_SANITIZE=ON -DNEARCAP_WERROR=ON -DNEARCAP_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-asan
stage_done "sanitizer build"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# The tests that drive Mesa through EGL or GLX (the rasterizer probe, the
# frame replay and lit frame, the pass-kind timing, `nearcap render`, `calibrate`,
# `evaluate`, `nearcap view` under Xvfb)
# run with every check but leak detection: llvmpipe's driver, loaded by EGL
# and unloaded at eglTerminate, leaves 9 small allocations (720 bytes) whose
# stacks end inside it.
egl_tests='^(LlvmpipeRasterizer|GlFrameReplayTest|EyeCountPassTest|GlHandleTest|LitFrameTest|LitShadingTest|GlslShadowProgramsTest|SideStripsTest|VolumeCullingGlTest|FarPlaneCapGlTest|RenderCommand|ViewCommand|ViewCommandErrors|PassKinds|CalibrateCommand|EvaluateCommand)(\.|$)'
# The tests of the documents, of the Python report's pages and of those pages
# in a browser, and of the benchmark helper scripts, run in the Release suite
# alone: what they check is text, Python and Chromium.  The C++ they start (the fixture's sweep, the commands
# the README's tour runs) is left unchecked by the sanitizers there, and
# checked by the commands' own tests; ReportInputs, report's own input checks,
# stays, but for its tests of what the script itself draws and reads
# (tests/report_inputs_test.cpp skips them there).
not_instrumented='^(Docs\.|Report$|ReportBrowser(\.|$)|BenchmarkScripts(\.|$))'
NEARCAP_STRESS_COUNT=150 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  ctest --test-dir build-asan --output-on-failure --no-tests=error -j2 -E "$egl_tests|$not_instrumented"
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 \
  ctest --test-dir build-asan --output-on-failure --no-tests=error -j2 -R "$egl_tests"
stage_done "sanitizer suite"
# Each fuzzer replays its corpus and regressions, then fuzzes for 6 s (the
# long runs are ./scripts/fuzz.sh 3600 and the campaigns: docs/development.md).
./scripts/fuzz.sh "${NEARCAP_FUZZ_SECONDS:-6}"
stage_done "fuzzers' build and runs"
