# Compiles through ccache when it is installed (HILRIG_CCACHE=OFF turns it off), so that a
# rebuild, a second build tree and a fresh clone of the same sources reuse earlier object files.
#
# Paths under the source tree's parent are rewritten relative to the build directory
# (CCACHE_BASEDIR) and the working directory is left out of the hash (CCACHE_NOHASHDIR), so two
# clones in different folders share entries; the price is that the debug information of a hit
# names the folder of the build that made it, which matters to no test. ccache hashes the
# compiler, every flag and the preprocessed source, so a hit is the object the compiler would
# make; CCACHE_DISABLE=1 in the environment bypasses it for a build. The cache lives where ccache
# keeps it by default ($CCACHE_DIR, else ~/.cache/ccache) and is held to HILRIG_CCACHE_MAX_SIZE.
option(HILRIG_CCACHE "Compile through ccache when it is found" ON)
set(HILRIG_CCACHE_MAX_SIZE "5G" CACHE STRING "Size limit of the ccache the build uses")
if(HILRIG_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(HILRIG_CCACHE_PROGRAM ccache)
  if(HILRIG_CCACHE_PROGRAM)
    cmake_path(GET CMAKE_SOURCE_DIR PARENT_PATH hilrig_ccache_base)
    set(CMAKE_CXX_COMPILER_LAUNCHER
        env CCACHE_BASEDIR=${hilrig_ccache_base} CCACHE_NOHASHDIR=true
        CCACHE_MAXSIZE=${HILRIG_CCACHE_MAX_SIZE} ${HILRIG_CCACHE_PROGRAM})
    message(STATUS "Compiling through ${HILRIG_CCACHE_PROGRAM}")
  endif()
endif()
