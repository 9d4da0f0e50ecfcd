# ccache, from Debian's package, compiles every target when it is installed: the cache outlives a build
# tree, so a second clone of the project (or CI after a session on the same machine) rebuilds only
# what changed. A machine without ccache builds the same way, uncached. -DPP5_CCACHE=OFF turns it off.
option(PP5_CCACHE "Compile through ccache when it is installed" ON)
if(PP5_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(PP5_CCACHE_PROGRAM ccache)
  if(PP5_CCACHE_PROGRAM)
    # Settings for this project's compiles only, left out of the user's ccache configuration:
    # - the precompiled headers (Pp5PrecompiledHeaders.cmake) need pch_defines and time_macros, and
    #   the header compiled a moment before its users needs the two mtime/ctime sloppinesses;
    # - paths below the source tree are hashed relative to it, and the build directory not at all,
    #   so clones in different places share their entries;
    # - in the fuzzing tree, the coverage allowlist's contents are part of every object's key: the
    #   command line names only its path, and an object instrumented under an older list would be
    #   reused after an edit (it once took a whole reader's coverage away in CI).
    set(pp5_ccache_extra_files)
    if(PP5_FUZZ_COVERAGE_ALLOWLIST)
      set(pp5_ccache_extra_files CCACHE_EXTRAFILES=${PP5_FUZZ_COVERAGE_ALLOWLIST})
    endif()
    set(CMAKE_CXX_COMPILER_LAUNCHER
        env
        ${pp5_ccache_extra_files}
        CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
        CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
        CCACHE_NOHASHDIR=1
        ${PP5_CCACHE_PROGRAM})
    message(STATUS "pp5sim: compiling through ${PP5_CCACHE_PROGRAM}")
  endif()
endif()
