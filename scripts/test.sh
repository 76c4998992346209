#!/usr/bin/env bash
# The README's test command: installs what is needed, builds build/ (Release, as scripts/demo.sh and the
# benchmarks use: every library, the program, every test and benchmark) and runs the whole test suite on it (CTest:
# unit tests, the CLI and hostile-input suites, a fast `robossis demo`); each stage prints its own time, and the
# measured times of a clean clone are in RELIABILITY.md. The same suite under AddressSanitizer and
# UndefinedBehaviorSanitizer is scripts/test-asan.sh; CI (.ci/run) runs both.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/stage.sh
stage "install the Debian packages that are missing" bash scripts/install-deps.sh
stage "configure and build build/ (Release; 7–13 min from cold on 2 cores, by the machine)" bash scripts/build.sh "$@"
stage "run the whole suite on build/" ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 1500
