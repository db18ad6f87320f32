# TUMBLE_CCACHE (default ON): compile through ccache when it is installed.
# The cache lives where ccache keeps it (~/.cache/ccache), outside the
# build tree, so a fresh clone or a new build directory reuses it. Paths are
# hashed relative to the source tree (base_dir), so two clones share hits;
# the sloppiness lets precompiled headers be cached too. Debug information
# records the build directory; mapping the source tree to "." keeps it out
# of the objects, so ccache need not hash the directory and a build with
# -g (the sanitizer builds' -g1) hits the cache from another clone too.
option(TUMBLE_CCACHE "Compile through ccache when it is installed" ON)
if(TUMBLE_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(TUMBLE_CCACHE_PROGRAM ccache)
  if(TUMBLE_CCACHE_PROGRAM)
    set(CMAKE_CXX_COMPILER_LAUNCHER
        ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${CMAKE_SOURCE_DIR}
        CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
        ${TUMBLE_CCACHE_PROGRAM})
    add_compile_options(-fdebug-prefix-map=${CMAKE_SOURCE_DIR}=.)
  endif()
endif()
