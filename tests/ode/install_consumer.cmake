# cmake -DBUILD_DIR= -DSOURCE_DIR= -DPREFIX= -DWORK= -DBUILD_TYPE= [-DEXTRA_FLAGS=] -P this
# Installs the build tree's kernels into PREFIX, then configures, builds and runs the outside
# project tests/ode/consumer against it. Any failing stage fails the test.
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
file(REMOVE_RECURSE "${PREFIX}" "${WORK}")
step(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
set(gen)
if(GENERATOR)
  set(gen -G "${GENERATOR}")
endif()
step(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/ode/consumer" -B "${WORK}" ${gen}
     -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_PREFIX_PATH=${PREFIX}
     "-DCMAKE_CXX_FLAGS=${EXTRA_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${EXTRA_FLAGS}")
step(${CMAKE_COMMAND} --build "${WORK}")
step("${WORK}/consumer")
