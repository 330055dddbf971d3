# Runs one case through `pcsim run` and compares its summary.json with the stored reference.
# Usage: cmake -DPCSIM=... -DCOMPARE=... -DCASE=... -DREFERENCE=... -DOUT=...
#              [-DSET=KEY=VALUE] [-DSET2=KEY=VALUE] [-DEXACT=ON] -P run_case.cmake
file(REMOVE_RECURSE "${OUT}")
set(_set_args)
foreach(_s IN ITEMS SET SET2)
  if(${_s})
    list(APPEND _set_args --set "${${_s}}")
  endif()
endforeach()
set(_exact)
if(EXACT)
  set(_exact --exact)
endif()
execute_process(COMMAND "${PCSIM}" run "${CASE}" ${_set_args} --out "${OUT}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pcsim run ${CASE} failed (exit ${rc}): ${err}")
endif()
execute_process(COMMAND "${COMPARE}" ${_exact} "${OUT}/summary.json" "${REFERENCE}"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "summary of ${CASE} differs from ${REFERENCE}")
endif()
