# pp5_project_target(<target> [PRECOMPILED <set>] [COMPILE_ALONE]): what every target of pp5sim's own
# gets, the warnings (Pp5Warnings.cmake) and precompiled headers (Pp5PrecompiledHeaders.cmake). A
# static library takes the `library` set unless told otherwise; a program takes none unless given one,
# since most are one file, for which a header compiled apart saves nothing.
#
# COMPILE_ALONE: each source compiles by itself, with no unity batch (Pp5UnityBuild.cmake) and no
# precompiled header, so that a missing include fails it. Under PP5_INCLUDE_CHECK every target outside
# tests/ is compiled so.
include(Pp5Warnings)
include(Pp5PrecompiledHeaders)

function(pp5_project_target target)
  cmake_parse_arguments(ARG "COMPILE_ALONE" "PRECOMPILED" "" ${ARGN})
  pp5_target_warnings(${target})
  get_target_property(type ${target} TYPE)
  get_target_property(source_dir ${target} SOURCE_DIR)
  string(FIND "${source_dir}/" "${PROJECT_SOURCE_DIR}/tests/" in_tests)
  if(PP5_INCLUDE_CHECK AND NOT in_tests EQUAL 0)
    set(ARG_COMPILE_ALONE ON)
  endif()
  if(ARG_COMPILE_ALONE)
    set_target_properties(${target} PROPERTIES PP5_COMPILE_ALONE ON)
    return()
  endif()
  if(NOT ARG_PRECOMPILED AND type STREQUAL "STATIC_LIBRARY")
    set(ARG_PRECOMPILED library)
  endif()
  if(ARG_PRECOMPILED)
    pp5_precompiled_headers(${target} ${ARG_PRECOMPILED})
  endif()
endfunction()
