#!/usr/bin/env bash
# Builds the libFuzzer targets (the `fuzz` preset, clang, in build-fuzz/) and runs each for SECONDS (default 30)
# from its shipped seed corpus. New inputs go to build-fuzz/corpus/<target>/, never into the source tree; a crash
# leaves its input as build-fuzz/crash-* and fails the script. Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
# With RUNS=N in the environment each target stops after N executions instead (SECONDS 0: no time limit), as the
# campaign of RELIABILITY.md ran: RUNS=10000000 scripts/fuzz.sh 0 TARGET. MAX_LEN=N bounds the input size (65536).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
shift || true
all=(fuzz_trajectory_csv fuzz_reference_trajectory fuzz_motive_reader fuzz_yaml_configs fuzz_atlas fuzz_setpoint_validation
     fuzz_setpoint_freshness fuzz_session_log fuzz_stl_mesh fuzz_panel_script)
if [ $# -gt 0 ]; then targets=("$@"); else targets=("${all[@]}"); fi
seeds() {
  case "$1" in
    fuzz_motive_reader) echo tests/calibration/data tests/fuzz/corpus/fuzz_motive_reader ;;
    fuzz_yaml_configs) echo data/config tests/fuzz/corpus/fuzz_yaml_configs ;;
    *) echo "tests/fuzz/corpus/$1" ;;
  esac
}
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake --preset fuzz "${launcher[@]}" >/dev/null
cmake --build --preset fuzz --parallel "$(nproc)" --target "${targets[@]}"
for t in "${targets[@]}"; do
  work="build-fuzz/corpus/$t"
  mkdir -p "$work"
  # shellcheck disable=SC2046
  (cd build-fuzz && "./tests/fuzz/$t" -max_total_time="$seconds" -runs="${RUNS:--1}" -timeout=10 -rss_limit_mb=2048 -max_len="${MAX_LEN:-65536}" \
      -print_final_stats=1 "../$work" $(for s in $(seeds "$t"); do echo "../$s"; done) 2>&1 | tail -n 12) ||
    { echo "fuzz.sh: $t failed (see build-fuzz/crash-*)" >&2; exit 1; }
done
