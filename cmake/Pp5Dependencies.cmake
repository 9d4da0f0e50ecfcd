# Every dependency comes from Debian's packages (see .ci/install-deps); none is vendored.
find_package(glm CONFIG REQUIRED)
find_package(fmt CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(tomlplusplus CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(TBB CONFIG REQUIRED)
find_package(ZLIB REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(tinyobjloader CONFIG REQUIRED)
# cpp-httplib (the browser tool's server) ships a pkg-config file, not a CMake package.
find_package(PkgConfig REQUIRED)
pkg_check_modules(CPP_HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)

# The Python module is built against Debian's own Python (where python3-numpy lives), not whatever
# python3 comes first on the PATH.
if(PP5_BUILD_PYTHON)
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 CONFIG REQUIRED)
endif()

# Debian's OpenImageIO 2.4 exports /usr/include/opencv4 as an include directory even when OpenCV's
# headers are absent, which makes every consumer fail to configure. Drop the path when it is missing.
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
if(_oiio_includes)
  set(_kept "")
  foreach(_dir IN LISTS _oiio_includes)
    if(_dir MATCHES "opencv" AND NOT EXISTS "${_dir}")
      continue()
    endif()
    list(APPEND _kept "${_dir}")
  endforeach()
  set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_kept}")
endif()

if(PP5_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(PP5_BUILD_BENCHMARKS)
  find_package(benchmark CONFIG REQUIRED)
endif()
find_package(Ceres CONFIG REQUIRED)
