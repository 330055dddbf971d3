# Runs one case through `pcsim run` and compares its summary.json with the stored reference.
# Usage: cmake -DPCSIM=... -DCOMPARE=... -DCASE=... -DREFERENCE=... -DOUT=... -P run_case.cmake
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${PCSIM}" run "${CASE}" --out "${OUT}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pcsim run ${CASE} failed (exit ${rc}): ${err}")
endif()
execute_process(COMMAND "${COMPARE}" "${OUT}/summary.json" "${REFERENCE}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "summary of ${CASE} differs from ${REFERENCE}")
endif()
