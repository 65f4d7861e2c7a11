#!/usr/bin/env bash
# Installs the packages, builds nearcap with warnings as errors and runs the
# whole test suite (ctest).  This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh -DNEARCAP_WERROR=ON -DNEARCAP_BUILD_TESTS=ON
ctest --test-dir build --output-on-failure -j2
