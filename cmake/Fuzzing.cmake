# TUMBLE_FUZZ=ON builds the libFuzzer targets of tests/fuzz (clang only).
# Every library is instrumented for coverage with AddressSanitizer and
# UndefinedBehaviorSanitizer (-fsanitize=fuzzer-no-link); only the fuzz
# targets link libFuzzer itself (tumble_fuzz_target).
if(TUMBLE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "TUMBLE_FUZZ needs clang (e.g. -DCMAKE_CXX_COMPILER=clang++-14)")
  endif()
  if(TUMBLE_SANITIZE)
    message(FATAL_ERROR "TUMBLE_FUZZ brings its own sanitizers; leave TUMBLE_SANITIZE empty")
  endif()
  set(_fuzz_sanitizers address,undefined)
  # -O1 keeps the run fast and the stacks readable; asserts stay on
  # whatever the build type, since a failed assert is a finding.
  add_compile_options(-fsanitize=fuzzer-no-link,${_fuzz_sanitizers} -fno-sanitize-recover=undefined
                      -fno-omit-frame-pointer -g -O1 -UNDEBUG)
  add_link_options(-fsanitize=${_fuzz_sanitizers})
endif()

# tumble_fuzz_target(name sources... LIBS libs...): a libFuzzer executable.
function(tumble_fuzz_target name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "LIBS")
  add_executable(${name} ${arg_UNPARSED_ARGUMENTS})
  target_link_libraries(${name} PRIVATE ${arg_LIBS})
  target_link_options(${name} PRIVATE -fsanitize=fuzzer)
  tumble_warnings(${name})
endfunction()
