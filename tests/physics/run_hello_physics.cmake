# cmake -DEXE=<hello_physics> -P run_hello_physics.cmake: runs the in-tree
# build of physics/examples/hello_physics and checks what it printed.
include(${CMAKE_CURRENT_LIST_DIR}/hello_physics_output.cmake)
execute_process(COMMAND ${EXE} OUTPUT_VARIABLE output RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${EXE} exited with ${result}")
endif()
check_hello_physics_output("${output}")
