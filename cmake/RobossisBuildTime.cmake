# What keeps the cold build within minutes on 2 cores (measured in BENCHMARKS.md, "Build time"). Every target of the
# project declares its kind with robossis_target_kind(<target> LIBRARY|TEST|APP):
#   LIBRARY  the libraries and the benchmarks, at the build type's optimisation (-O3 in Release);
#   TEST     the GoogleTest binaries, and
#   APP      the robossis program's own units: at -O1 in Release. They only parse, call and print (the real-time and
#            numeric work is in the libraries), and at -O3 they were half of the cold build's compile time.
#
# Each kind has one precompiled header, compiled once and reused by every target of that kind (CMake's REUSE_FROM;
# GCC requires the same compile flags of a precompiled header's users, and -Winvalid-pch warns where they differ):
#   LIBRARY  the standard library, Eigen and nlohmann-json;
#   TEST     the same, GoogleTest and GoogleMock;
#   APP      the same and CLI11.
# ROBOSSIS_PCH=OFF builds every unit from its own includes: the fuzz preset does, so CI compiles the libraries once
# without precompiled headers and a missing #include cannot hide behind them.
option(ROBOSSIS_PCH "Precompile the heavy third-party headers (std, Eigen, nlohmann-json, GoogleTest, CLI11)" ON)

set(_robossis_pch_common
  <algorithm> <array> <atomic> <chrono> <cmath> <cstdint> <cstdio> <cstdlib> <cstring> <filesystem> <fstream>
  <functional> <iostream> <limits> <map> <memory> <optional> <random> <sstream> <stdexcept> <string> <string_view>
  <thread> <utility> <vector>
  <Eigen/Core> <Eigen/Geometry>
  <nlohmann/json.hpp>)

# The glue kinds' optimisation (the last -O on the command line wins over CMAKE_CXX_FLAGS_RELEASE's -O3).
function(_robossis_glue_optimization target)
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
endfunction()

# The target that owns a kind's precompiled header: one empty unit, linked to nothing of the project's.
function(_robossis_add_pch_owner kind)
  set(name robossis_pch_${kind})
  set(source "${PROJECT_BINARY_DIR}/pch/${name}.cc")
  if(NOT EXISTS "${source}")
    file(WRITE "${source}" "// Owner of the ${kind} precompiled header (cmake/RobossisBuildTime.cmake).\n")
  endif()
  add_library(${name} STATIC "${source}")
  target_link_libraries(${name} PRIVATE Eigen3::Eigen nlohmann_json::nlohmann_json ${ARGN})
  if(NOT kind STREQUAL "library")
    _robossis_glue_optimization(${name})
  endif()
endfunction()

if(ROBOSSIS_PCH)
  _robossis_add_pch_owner(library)
  target_precompile_headers(robossis_pch_library PRIVATE ${_robossis_pch_common})
  _robossis_add_pch_owner(app CLI11::CLI11)
  target_precompile_headers(robossis_pch_app PRIVATE ${_robossis_pch_common} <CLI/CLI.hpp>)
endif()

# The TEST kind's header, once GoogleTest is found (tests/CMakeLists.txt).
function(robossis_add_test_pch)
  if(ROBOSSIS_PCH)
    _robossis_add_pch_owner(test GTest::gtest GTest::gmock)
    target_precompile_headers(robossis_pch_test PRIVATE ${_robossis_pch_common} <gtest/gtest.h> <gmock/gmock.h>)
  endif()
endfunction()

function(robossis_target_kind target kind)
  if(NOT kind MATCHES "^(LIBRARY|TEST|APP)$")
    message(FATAL_ERROR "robossis_target_kind(${target} ${kind}): expected LIBRARY, TEST or APP")
  endif()
  string(TOLOWER "${kind}" kind)
  if(NOT kind STREQUAL "library")
    _robossis_glue_optimization(${target})
  endif()
  if(ROBOSSIS_PCH)
    target_precompile_headers(${target} REUSE_FROM robossis_pch_${kind})
  endif()
endfunction()
