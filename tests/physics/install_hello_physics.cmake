# cmake -DPHYSICS_BUILD=<build>/physics -DEXAMPLES=<src>/physics/examples
#       -DWORK=<dir> -DCXX=<compiler> [-DLINK_FLAGS=...] -P install_hello_physics.cmake
# Installs tumble_physics from the tree's build into WORK/prefix, configures
# physics/examples against that prefix alone (find_package) in a fresh build
# directory, builds hello_physics, runs it and checks what it printed.
include(${CMAKE_CURRENT_LIST_DIR}/hello_physics_output.cmake)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK})
run(${CMAKE_COMMAND} --install ${PHYSICS_BUILD} --prefix ${WORK}/prefix --component physics)
if(NOT EXISTS ${WORK}/prefix/include/tumble/physics/world.h OR EXISTS ${WORK}/prefix/include/tumble/physics/contact_solver.h)
  message(FATAL_ERROR "the prefix does not hold exactly the public headers")
endif()
run(${CMAKE_COMMAND} -S ${EXAMPLES} -B ${WORK}/build -G Ninja -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${WORK}/prefix "-DCMAKE_EXE_LINKER_FLAGS=${LINK_FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK}/build)
execute_process(COMMAND ${WORK}/build/hello_physics OUTPUT_VARIABLE output RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "hello_physics exited with ${result}")
endif()
check_hello_physics_output("${output}")
