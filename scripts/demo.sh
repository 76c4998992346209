#!/usr/bin/env bash
# Installs, builds and runs `robossis demo` on the default configuration; the report goes to demo-report/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/robossis demo --out demo-report "$@"
