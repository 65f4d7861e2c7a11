#!/usr/bin/env bash
# Fails when a C++ source differs from .clang-format's layout (clang-format 14).
set -euo pipefail
cd "$(dirname "$0")/.."
files=$(git ls-files '*.cpp' '*.hpp')
if ! clang-format-14 --dry-run --Werror $files; then
  echo "check-format: run 'clang-format-14 -i \$(git ls-files \"*.cpp\" \"*.hpp\")'"
  exit 1
fi
echo "check-format: $(echo "$files" | wc -w) files formatted"
