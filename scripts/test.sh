#!/usr/bin/env bash
# The README's test command, and CI's: installs what is needed, builds the `asan` preset (build-asan/: the whole
# project, benchmarks included, with AddressSanitizer + UndefinedBehaviorSanitizer) and runs the whole test suite
# under the sanitizers (CTest: unit tests, the CLI and hostile-input suites, a fast `robossis demo`). Every heap
# error, leak or undefined behaviour fails the test that hit it. The same suite on the optimised build that
# `scripts/demo.sh` and the benchmarks use: scripts/test-release.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)  # not a dependency
cmake --preset asan "${launcher[@]}" "$@"
cmake --build --preset asan --parallel "$(nproc)"
# Sanitized code runs ~2-5x slower than Release: a longer per-test timeout than scripts/test-release.sh.
ctest --preset asan --parallel "$(nproc)" --timeout 3000
