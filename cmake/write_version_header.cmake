# Writes OUT (a header defining ROBOSSIS_VERSION and ROBOSSIS_GIT_REVISION) at every build, touching it only when
# the revision changed, so `robossis --version` names the commit it was built from without rebuilding on every run.
# Inputs: -DSOURCE_DIR=... -DVERSION=... -DOUT=...
set(revision "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" describe --always --dirty --abbrev=12
                  OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
  if(NOT failed AND described)
    set(revision "${described}")
  endif()
endif()
set(text "#pragma once\n#define ROBOSSIS_VERSION \"${VERSION}\"\n#define ROBOSSIS_GIT_REVISION \"${revision}\"\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
