# Precompiled headers: the standard and third-party headers most of pp5sim's files include (the
# standard library, nlohmann/json, fmt, GLM, oneTBB; GoogleTest for the tests, CLI11 for the command
# line) are parsed once per build, not once per file, which was most of a file's compile time.
#
# Each set is compiled once, by a host target of its own (one empty source), and reused by every
# target that asks for it. Reusing needs the same compile options, so libraries (-fPIC outside the
# sanitizer builds) and programs (-fPIE) get a host each, and a user links the same third-party targets
# as its host (fmt::fmt defines FMT_SHARED, which the compiled header was made with).
#
# The sources still include what they use: configure with -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON to
# compile without them (.ci/tsan does, so a missing include still fails CI).
#
# Not with clang through ccache: clang writes the build tree's absolute path into the compiled header,
# and ccache hashes the header's bytes into the key of every file that uses it, so a checkout in
# another folder would compile every such file again (a second clone's sanitizer build took 330 s
# against 352 s for the first). There the unity batches alone share the headers, and every object is
# found in the cache. GCC's compiled headers do not name the tree and stay.
set(PP5_PCH_CACHEABLE ON)
if(CMAKE_CXX_COMPILER_ID MATCHES "Clang" AND CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  set(PP5_PCH_CACHEABLE OFF)
  message(STATUS "pp5sim: no precompiled headers (clang's name the build tree, which keeps ccache from sharing objects between checkouts)")
endif()
set(PP5_PCH_STANDARD
  <algorithm> <array> <chrono> <cmath> <cstddef> <cstdint> <filesystem> <functional> <limits> <map>
  <memory> <optional> <set> <span> <sstream> <stdexcept> <string> <string_view> <utility> <vector>)
set(PP5_PCH_THIRD_PARTY
  <nlohmann/json.hpp> <fmt/format.h> <glm/vec3.hpp> <glm/vec4.hpp> <glm/geometric.hpp>
  <tbb/parallel_for.h> <tbb/blocked_range.h>)
set(PP5_PCH_THIRD_PARTY_TARGETS nlohmann_json::nlohmann_json fmt::fmt glm::glm TBB::tbb)

# The sets: `library` for the static libraries, `tests` for the GoogleTest binaries, `command_line`
# for pp5sim's commands.
set(PP5_PCH_SETS library tests command_line)
set(PP5_PCH_library_HEADERS ${PP5_PCH_STANDARD} ${PP5_PCH_THIRD_PARTY})
set(PP5_PCH_tests_HEADERS ${PP5_PCH_STANDARD} ${PP5_PCH_THIRD_PARTY} <gtest/gtest.h> <gmock/gmock.h>)
set(PP5_PCH_command_line_HEADERS ${PP5_PCH_STANDARD} ${PP5_PCH_THIRD_PARTY} <CLI/CLI.hpp>)
set(PP5_PCH_library_TARGETS ${PP5_PCH_THIRD_PARTY_TARGETS})
set(PP5_PCH_tests_TARGETS ${PP5_PCH_THIRD_PARTY_TARGETS} GTest::gtest GTest::gmock)
set(PP5_PCH_command_line_TARGETS ${PP5_PCH_THIRD_PARTY_TARGETS} CLI11::CLI11)

# pp5_test_optimization(<target>): a test program's own optimisation (PP5_TEST_OPTIMIZATION, top
# CMakeLists.txt). It comes after the build type's flags on the command line, so it wins.
function(pp5_test_optimization target)
  if(PP5_TEST_OPTIMIZATION)
    target_compile_options(${target} PRIVATE ${PP5_TEST_OPTIMIZATION})
  endif()
endfunction()

# The host of a set, made on first use.
function(_pp5_pch_host set out_host)
  set(host pp5_pch_${set})
  set(${out_host} ${host} PARENT_SCOPE)
  if(TARGET ${host})
    return()
  endif()
  set(source ${PROJECT_BINARY_DIR}/precompiled_headers/${host}.cpp)
  file(CONFIGURE OUTPUT ${source} CONTENT "// Compiles the precompiled headers of the ${set} set (cmake/Pp5PrecompiledHeaders.cmake).\n")
  add_library(${host} OBJECT ${source})
  # Libraries are -fPIC outside the sanitizer builds; programs are position independent by the
  # compiler's default (-fPIE), which an object library without -fPIC matches.
  set(pic OFF)
  if(set STREQUAL "library" AND CMAKE_POSITION_INDEPENDENT_CODE)
    set(pic ON)
  endif()
  set_target_properties(${host} PROPERTIES POSITION_INDEPENDENT_CODE ${pic})
  target_link_libraries(${host} PRIVATE ${PP5_PCH_${set}_TARGETS})
  pp5_target_warnings(${host})
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    # Without it clang stamps the header with its build time, and ccache will not cache its users.
    target_compile_options(${host} PRIVATE "SHELL:-Xclang -fno-pch-timestamp")
  endif()
  if(set STREQUAL "tests")
    pp5_test_optimization(${host})  # the test programs' optimisation, which the compiled header must match
  endif()
  target_precompile_headers(${host} PRIVATE ${PP5_PCH_${set}_HEADERS})
endfunction()

# pp5_precompiled_headers(<target> <set>): <target> compiles with the set's precompiled headers.
function(pp5_precompiled_headers target set)
  if(NOT set IN_LIST PP5_PCH_SETS)
    message(FATAL_ERROR "pp5_precompiled_headers: no set '${set}' (one of ${PP5_PCH_SETS})")
  endif()
  if(CMAKE_DISABLE_PRECOMPILE_HEADERS OR NOT PP5_PCH_CACHEABLE)
    return()
  endif()
  _pp5_pch_host(${set} host)
  target_link_libraries(${target} PRIVATE ${PP5_PCH_${set}_TARGETS})
  target_precompile_headers(${target} REUSE_FROM ${host})
endfunction()
