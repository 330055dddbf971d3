# `mpirun -np 2 pcsim sweep` writes the same sweep.csv as `pcsim sweep --jobs 1` (the real
# integrator, shortened to t_end = 0.02 s to stay fast). Run by CTest with -DPCSIM=... -DMPIEXEC=...
# -DCASE=... -DOUT=...
file(REMOVE_RECURSE "${OUT}")
set(_args sweep "${CASE}" --set solver.t_end=0.02 --vary parameters.omega=260,300
          --vary initial.s0=0.2,0.4)
execute_process(COMMAND "${PCSIM}" ${_args} --jobs 1 --out "${OUT}/single" RESULT_VARIABLE rc1)
execute_process(COMMAND "${MPIEXEC}" -np 2 --oversubscribe "${PCSIM}" ${_args} --jobs 1
                        --out "${OUT}/ranks" RESULT_VARIABLE rc2)
if(NOT rc1 EQUAL 0 OR NOT rc2 EQUAL 0)
  message(FATAL_ERROR "pcsim sweep failed: single ${rc1}, mpirun ${rc2}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${OUT}/single/sweep.csv"
                        "${OUT}/ranks/sweep.csv" RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "the 2-rank sweep.csv differs from the 1-job one")
endif()
message(STATUS "2-rank sweep.csv == 1-job sweep.csv")
