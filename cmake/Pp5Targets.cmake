# pp5_project_target(<target> [PRECOMPILED <set>]): what every target of pp5sim's own gets, the
# warnings (Pp5Warnings.cmake) and precompiled headers (Pp5PrecompiledHeaders.cmake). A static library
# takes the `library` set unless told otherwise; a program takes none unless given one, since most are
# one file, for which a header compiled apart saves nothing.
include(Pp5Warnings)
include(Pp5PrecompiledHeaders)

function(pp5_project_target target)
  cmake_parse_arguments(ARG "" "PRECOMPILED" "" ${ARGN})
  pp5_target_warnings(${target})
  get_target_property(type ${target} TYPE)
  if(NOT ARG_PRECOMPILED AND type STREQUAL "STATIC_LIBRARY")
    set(ARG_PRECOMPILED library)
  endif()
  if(ARG_PRECOMPILED)
    pp5_precompiled_headers(${target} ${ARG_PRECOMPILED})
  endif()
endfunction()
