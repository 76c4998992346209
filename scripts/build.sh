#!/usr/bin/env bash
# Configures and builds the project in build/ (Release, Ninja). Extra arguments go to CMake's configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache, where installed, shares compiled objects between checkouts (it is not a dependency).
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "$@"
cmake --build build --parallel "$(nproc)"
