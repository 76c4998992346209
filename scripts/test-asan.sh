#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer (the `asan` preset, in build-asan/) and
# runs it: every heap error, leak or undefined behaviour fails the test that hit it. CI runs it after scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake --preset asan "${launcher[@]}" "$@"
cmake --build --preset asan --parallel "$(nproc)"
# Sanitized code runs ~2-5x slower than Release: a longer per-test timeout than scripts/test.sh.
ctest --preset asan --parallel "$(nproc)" --timeout 3000
