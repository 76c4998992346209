#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (CTest: unit tests and a fast `robossis demo`).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 1500
