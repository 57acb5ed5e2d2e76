# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal_add_library(<layer> SOURCES <src>... [PUBLIC <dep>...]
#                       [PRIVATE <dep>...])
# One layer's library, the same for every folder: the target
# activecal_<layer> from SOURCES, its include/ folder public (the build
# tree's, and the install tree's include directory), linked PUBLIC and
# PRIVATE as given, exported (ActivecalInstall.cmake) as activecal::<layer>,
# with the project's warnings, and the alias activecal::<layer> for use in
# the build tree.
include_guard(GLOBAL)

function(activecal_add_library layer)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;PUBLIC;PRIVATE")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR
      "activecal_add_library(${layer}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  set(target activecal_${layer})
  add_library(${target} ${ARG_SOURCES})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${layer})
  activecal_warnings(${target})
  add_library(activecal::${layer} ALIAS ${target})
endfunction()
