#!/usr/bin/env bash
# Installs, builds build/ (Release, as scripts/demo.sh and the benchmarks do) and runs the whole test suite on it
# (CTest: unit tests and a fast `robossis demo`). About a third of the time of scripts/test.sh, which runs the same
# suite under the sanitizers and is what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 1500
