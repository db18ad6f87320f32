# TUMBLE_SANITIZE=address,undefined or thread instruments every target.
# The line tables of -g1 are enough for the reports' stacks and cost far
# less to compile and link than full debug information. scripts/test.sh
# builds these at -Og with assertions on (CMAKE_BUILD_TYPE=Debug with
# CMAKE_CXX_FLAGS_DEBUG=-Og).
if(TUMBLE_SANITIZE)
  set(_flags -fsanitize=${TUMBLE_SANITIZE} -fno-omit-frame-pointer -g1)
  if(TUMBLE_SANITIZE MATCHES "undefined")
    list(APPEND _flags -fno-sanitize-recover=undefined)
  endif()
  # GCC's -Wmaybe-uninitialized gives false positives under the sanitizers'
  # instrumentation (in Boost.Beast's parser, say); its manual says as much.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    list(APPEND _flags -Wno-maybe-uninitialized)
    # Asio orders handlers with std::atomic_thread_fence, which GCC warns
    # ThreadSanitizer cannot see; its queues' mutexes, which it can, carry
    # the same ordering.
    if(TUMBLE_SANITIZE MATCHES "thread")
      list(APPEND _flags -Wno-tsan)
    endif()
  endif()
  add_compile_options(${_flags})
  add_link_options(-fsanitize=${TUMBLE_SANITIZE})
  # An instrumented program is position-independent by default, and its
  # globals' metadata makes about a million relative relocations that the
  # loader applies at every start, in each of the thousands of test and
  # server processes a run of the suite starts. Linked at a fixed address it
  # has none (docs/development.md "Sanitizers"). ThreadSanitizer's programs
  # start quickly and stay position-independent.
  if(TUMBLE_SANITIZE MATCHES "address")
    add_link_options(-no-pie)
  endif()
endif()
