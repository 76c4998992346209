# `cmake --install`: the robossis program, the libraries and their headers, the data folder, and a CMake package
# (find_package(robossis) → robossis::core, robossis::robot, robossis::geometry, ...). CPack makes a .deb.
# A new library joins the package by adding its target to ROBOSSIS_INSTALLED_LIBRARIES and its header folder to
# ROBOSSIS_INSTALLED_HEADER_DIRS.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ROBOSSIS_INSTALLED_LIBRARIES
  robossis_core robossis_robot robossis_geometry robossis_sim robossis_calibration robossis_haptics
  robossis_actuation robossis_transfer robossis_drivers robossis_teleop)
# Header folders, relative to the source tree (headers are included as "robot/rsr_model.h", "src/core/config.h").
set(ROBOSSIS_INSTALLED_HEADER_DIRS src/core robot geometry calibration haptics src/teleop)

set(ROBOSSIS_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/robossis)
set(ROBOSSIS_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/robossis)

foreach(lib IN LISTS ROBOSSIS_INSTALLED_LIBRARIES)
  string(REPLACE "robossis_" "" short ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
  target_include_directories(${lib} INTERFACE $<INSTALL_INTERFACE:${ROBOSSIS_INSTALL_INCLUDEDIR}>)
  # A sanitized build's libraries need the sanitizers' run-time libraries in every program that links them.
  if(ROBOSSIS_SANITIZE)
    target_link_options(${lib} INTERFACE $<INSTALL_INTERFACE:-fsanitize=address,undefined>)
  endif()
endforeach()

install(TARGETS robossis RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${ROBOSSIS_INSTALLED_LIBRARIES} EXPORT robossisTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(dir IN LISTS ROBOSSIS_INSTALLED_HEADER_DIRS)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${ROBOSSIS_INSTALL_INCLUDEDIR}/${dir}
          FILES_MATCHING PATTERN "*.h")
endforeach()
# The data folder (configs, reference data) and the figure scripts, where the installed program looks for them.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/robossis/data)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scripts/plots/ DESTINATION ${CMAKE_INSTALL_DATADIR}/robossis/plots)

install(EXPORT robossisTargets NAMESPACE robossis:: DESTINATION ${ROBOSSIS_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/robossisConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/robossisConfig.cmake INSTALL_DESTINATION ${ROBOSSIS_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/robossisConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/robossisConfig.cmake ${PROJECT_BINARY_DIR}/robossisConfigVersion.cmake
        DESTINATION ${ROBOSSIS_INSTALL_CMAKEDIR})

# Debian package: dependencies are Debian's package names, computed from the linked shared libraries
# (dpkg-shlibdeps), plus the -dev packages a consumer of the CMake package needs for the headers.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME robossis)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "Robossis workbench maintainers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Robossis haptic workbench: sigma.7 leader, RSR follower, simulation")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libeigen3-dev, libyaml-cpp-dev, nlohmann-json3-dev, libfcl-dev, libvtk9-dev, libopencv-dev, libbullet-dev")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
include(CPack)
