# TUMBLE_CCACHE (default ON): compile through ccache when it is installed.
# The cache lives where ccache keeps it (~/.cache/ccache), outside the
# build tree, so a fresh clone or a new build directory reuses it. Paths are
# hashed relative to the source tree (base_dir), so two clones share hits;
# the sloppiness lets precompiled headers be cached too. Debug information
# records the build directory, and __FILE__ (in assert and in gtest's and
# spdlog's macros) the path a file was included by, which in a unity build
# is absolute. Mapping the source tree to "." (-ffile-prefix-map: debug
# information and macros both) keeps the clone's path out of the objects
# and out of the preprocessed text ccache hashes, so a new clone hits the
# cache too. ccache hashes the locale variables (they choose the language
# of GCC's messages), so compiles run without them: a build in a container,
# where none is set, then hits what the host compiled (docker/Dockerfile).
option(TUMBLE_CCACHE "Compile through ccache when it is installed" ON)
if(TUMBLE_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(TUMBLE_CCACHE_PROGRAM ccache)
  if(TUMBLE_CCACHE_PROGRAM)
    set(CMAKE_CXX_COMPILER_LAUNCHER
        ${CMAKE_COMMAND} -E env --unset=LANG --unset=LC_ALL --unset=LC_CTYPE --unset=LC_MESSAGES
        CCACHE_BASEDIR=${CMAKE_SOURCE_DIR}
        CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
        ${TUMBLE_CCACHE_PROGRAM})
    add_compile_options(-ffile-prefix-map=${CMAKE_SOURCE_DIR}=.)
  endif()
endif()
