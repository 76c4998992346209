# The CTest properties of the tests that run real-time loops: rt::PeriodicLoop at SCHED_FIFO (the teleop session on
# the real clock, the panel's own session, a follower unit's loop, the link's two units as processes), a servo
# thread at SCHED_FIFO, or HAL's real-time threads (halrun). They run alone, RUN_SERIAL: on the 2-core CI machine
# under the sanitizers, two such tests' SCHED_FIFO loops side by side starve each other. HAL tests also take the HAL
# lock: there is one HAL per machine.
#
# robossis_realtime_test_properties(<out-var> [HAL]) sets <out-var> to those properties, for the PROPERTIES of
# gtest_discover_tests() (robossis_add_gtest's REALTIME and HAL) or of set_tests_properties().
function(robossis_realtime_test_properties out_var)
  cmake_parse_arguments(ARG "HAL" "" "" ${ARGN})
  set(properties RUN_SERIAL TRUE)
  if(ARG_HAL)
    list(APPEND properties RESOURCE_LOCK linuxcnc_hal)
  endif()
  set(${out_var} ${properties} PARENT_SCOPE)
endfunction()
