#!/usr/bin/env bash
# Installs, builds and runs `robossis demo` on the default configuration; the report goes to demo-report/.
# Each stage says what it does and how long it took; the build shows ninja's [done/total] progress.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/stage.sh
stage "install the Debian packages that are missing" bash scripts/install-deps.sh
stage "configure and build build/ (Release; 7–13 min from cold on 2 cores, by the machine)" bash scripts/build.sh
stage "run robossis demo (each section reports its time)" ./build/robossis demo --out demo-report "$@"
echo "demo.sh: report in demo-report/report.md; ${SECONDS} s in all"
