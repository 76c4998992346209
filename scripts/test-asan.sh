#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer (the `asan` preset, in build-asan/) and
# runs it: every heap error, leak or undefined behaviour fails the test that hit it.
#   bash scripts/test-asan.sh        the whole suite (ctest --preset asan)
#   bash scripts/test-asan.sh --ci   what CI runs within its 90 minutes on 2 cores: the unit tests of the real-time
#                                    units (loops, follower and leader units, set-point validation, flight
#                                    recorder, link logic), the kinematics and feasible-motion guard, the workspace
#                                    geometry and every CSV/YAML reader (core, calibration); RELIABILITY.md
set -euo pipefail
cd "$(dirname "$0")/.."
ci_tests=(core_test rt_test calibration_test geometry_test robot_kinematics_test robot_feasible_motion_test
          teleop_setpoint_validator_test teleop_recorder_test teleop_follower_unit_test teleop_leader_test
          teleop_loop_test link_logic_test)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ "${1:-}" != "--ci" ]; then
  cmake --preset asan "${launcher[@]}" "$@"
  cmake --build --preset asan --parallel "$(nproc)"
  # Sanitized code runs ~2-5x slower than Release: a longer per-test timeout than scripts/test.sh.
  ctest --preset asan --parallel "$(nproc)" --timeout 3000
  exit 0
fi
cmake --preset asan "${launcher[@]}" >/dev/null
cmake --build --preset asan --parallel "$(nproc)" --target "${ci_tests[@]}"
export ROBOSSIS_DATA_DIR="$PWD/data" ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=()
for t in "${ci_tests[@]}"; do
  binary=$(find build-asan/tests -name "$t" -type f -perm -u+x | head -n 1)
  echo "== $t (ASan+UBSan)"
  "$binary" --gtest_brief=1 || failed+=("$t")
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "test-asan.sh: failed under ASan+UBSan: ${failed[*]}" >&2
  exit 1
fi
echo "test-asan.sh: ${#ci_tests[@]} test binaries clean under ASan+UBSan"
