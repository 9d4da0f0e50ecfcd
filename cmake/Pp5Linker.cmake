# Links with LLVM's lld when the toolchain can use it (Debian's `lld`, which .ci/install-deps installs
# with the test packages). The GNU linker takes about 2 s for each of the thirty-odd executables of a
# test build and longer with the sanitizers' debug lines; lld takes a fifth of that, and the objects and
# programs are the same either way. Without lld (`.ci/install-deps main`) the default linker is used.
# -DPP5_USE_LLD=OFF keeps the default linker.
#
# Executables only: the Python module is one link, and pybind11 compiles it with GCC's link-time
# optimisation, whose objects only GCC's own linker plugin reads (lld would link an empty module).
option(PP5_USE_LLD "Link with lld when the compiler can" ON)
if(PP5_USE_LLD)
  include(CheckLinkerFlag)
  check_linker_flag(CXX -fuse-ld=lld PP5_LINKER_LLD_WORKS)
  if(PP5_LINKER_LLD_WORKS)
    string(APPEND CMAKE_EXE_LINKER_FLAGS " -fuse-ld=lld")
  endif()
endif()
