# tumble_warnings(target): the project's warning set, fatal with TUMBLE_WERROR.
# The one list of flags: the physics project uses it alone, and the root
# project includes this file for every other target.
option(TUMBLE_WERROR "Treat warnings as errors" OFF)

# A unity build (CMAKE_UNITY_BUILD, scripts/build.sh's default) compiles a
# target's files included into a few generated ones, so each file is no
# longer the main file and GCC warns of every class that holds a type of
# the file's anonymous namespace, which is the point of that namespace.
if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  add_compile_options(-Wno-subobject-linkage)
endif()

function(tumble_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
    -Wcast-align -Woverloaded-virtual -Wconversion -Wsign-conversion
    -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
  # GCC 12 reports a false -Wrestrict inside libstdc++ for
  # `"literal" + std::string&&` at -O2 (GCC bug 105329, fixed in 13).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(TUMBLE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
