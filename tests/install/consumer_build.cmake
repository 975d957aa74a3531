# `cmake --install` of the build into a fresh prefix, then the consumer
# project (tests/install/consumer) configured against that prefix with
# find_package(sabus), built and run. Called by ctest with
#   -DBUILD_DIR= -DCONSUMER_DIR= -DWORK_DIR= -DGENERATOR= -DCXX_COMPILER=
# run(NAME COMMAND...): runs a step, fails the test with its output on error.
function(run name)
  execute_process(COMMAND ${ARGN} OUTPUT_VARIABLE out ERROR_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name} failed (exit ${rc}):\n${out}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
run("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
run("configure the consumer" ${CMAKE_COMMAND} -S "${CONSUMER_DIR}" -B "${WORK_DIR}/build" -G "${GENERATOR}"
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_PREFIX_PATH=${prefix})
# The package found must be the one just installed, not one on the system.
file(STRINGS "${WORK_DIR}/build/CMakeCache.txt" found REGEX "^sabus_DIR:")
file(GLOB expected_dir LIST_DIRECTORIES true "${prefix}/lib*/cmake/sabus" "${prefix}/lib/*/cmake/sabus")
if(NOT found MATCHES "=${expected_dir}$")
  message(FATAL_ERROR "find_package(sabus) found ${found}, expected ${expected_dir}")
endif()
run("build the consumer" ${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("run the consumer" "${WORK_DIR}/build/consumer")
if(NOT out STREQUAL "Device Status Poll: 02 32 31 03 02\n")
  message(FATAL_ERROR "consumer printed: ${out}")
endif()
message(STATUS "consumer built against ${expected_dir}: ${out}")
