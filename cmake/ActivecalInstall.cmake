# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Install rules: the libraries, the public headers only, the programs, and a
# CMake package so that other projects can find_package(activecal) and link
# activecal::activecal.
include(CMakePackageConfigHelpers)

install(TARGETS activecal_core activecal_io activecal_residuals
  activecal_selection activecal_kinematics activecal_cell activecal_estimation
  activecal_calibration activecal_report activecal_driver activecal
  EXPORT activecalTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(layer core io residuals selection kinematics cell estimation calibration report
    driver)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/include/activecal
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    FILES_MATCHING PATTERN "*.h")
endforeach()
if(ACTIVECAL_BUILD_APPS)
  install(TARGETS activecal_evaluate activecal_identify activecal_select activecal_simulate
    activecal_puma_paper activecal_monte_carlo activecal_active activecal_sim_cell
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

set(ACTIVECAL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/activecal)
install(EXPORT activecalTargets
  NAMESPACE activecal::
  DESTINATION ${ACTIVECAL_CMAKE_DIR})
configure_package_config_file(
  ${CMAKE_CURRENT_LIST_DIR}/activecalConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/activecalConfig.cmake
  INSTALL_DESTINATION ${ACTIVECAL_CMAKE_DIR})
write_basic_package_version_file(
  ${CMAKE_CURRENT_BINARY_DIR}/activecalConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMajorVersion)
install(FILES
  ${CMAKE_CURRENT_BINARY_DIR}/activecalConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/activecalConfigVersion.cmake
  DESTINATION ${ACTIVECAL_CMAKE_DIR})
