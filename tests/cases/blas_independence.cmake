# pcsim's results do not depend on the system BLAS/LAPACK's settings (issue 14): the same case,
# on a path that calls LAPACK (Radau with solver.linear_algebra = lapack), run under different
# OpenBLAS thread counts and core types, gives bit-identical summaries. pcsim binds Debian's
# reference LAPACK by path and RUNPATH, so OpenBLAS (the system alternative once Siconos is
# installed) is not even loaded; the test also checks that from the process's own map of
# libraries (LD_DEBUG output).
# Usage: cmake -DPCSIM=... -DCOMPARE=... -DCASE=... -DOUT=... -P blas_independence.cmake
file(REMOVE_RECURSE "${OUT}")
set(settings
  "OPENBLAS_NUM_THREADS=1"
  "OPENBLAS_NUM_THREADS=2"
  "OPENBLAS_NUM_THREADS=2;OPENBLAS_CORETYPE=Prescott"
  "OPENBLAS_NUM_THREADS=1;OPENBLAS_CORETYPE=Haswell"
  "OPENBLAS_NUM_THREADS=2;OPENBLAS_CORETYPE=Sandybridge")
set(i 0)
foreach(s IN LISTS settings)
  string(REPLACE ";" " " env_args "${s}")
  separate_arguments(env_list UNIX_COMMAND "${env_args}")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env_list} LD_DEBUG=libs
                          "${PCSIM}" run "${CASE}" --set solver.method=radau
                          --set solver.linear_algebra=lapack --set solver.t_end=0.5
                          --out "${OUT}/run${i}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pcsim run under ${s} failed (exit ${rc}): ${err}")
  endif()
  if(err MATCHES "libopenblas")
    message(FATAL_ERROR "pcsim loaded OpenBLAS under ${s}: its LAPACK must be the pinned reference one")
  endif()
  if(i GREATER 0)
    execute_process(COMMAND "${COMPARE}" --exact "${OUT}/run${i}/summary.json" "${OUT}/run0/summary.json"
                    RESULT_VARIABLE crc OUTPUT_VARIABLE cout)
    if(NOT crc EQUAL 0)
      message(FATAL_ERROR "summary under ${s} differs from the first run:\n${cout}")
    endif()
  endif()
  math(EXPR i "${i} + 1")
endforeach()
message("identical summaries under ${i} BLAS settings; OpenBLAS never loaded")
