#!/usr/bin/env bash
# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer: installs what is needed, builds the
# `asan` preset (build-asan/: the whole project, benchmarks included) and runs CTest under the sanitizers. Every heap
# error, leak or undefined behaviour fails the test that hit it. CI runs it after scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/stage.sh
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)  # not a dependency
stage "install the Debian packages that are missing" bash scripts/install-deps.sh
stage "configure build-asan/ (ASan+UBSan)" cmake --preset asan "${launcher[@]}" "$@"
stage "build build-asan/" cmake --build --preset asan --parallel "$(nproc)"
# Sanitized code runs ~2-5x slower than Release: a longer per-test timeout than scripts/test.sh. Tests labelled
# `long` are statistical acceptance runs (hundreds of seeded takes through code the shorter tests already run under
# the sanitizers): they run in the Release suite only, where they take minutes rather than half an hour.
stage "run the whole suite under the sanitizers" ctest --preset asan --parallel "$(nproc)" --timeout 3000 --label-exclude long
