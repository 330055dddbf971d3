# Component study: sweeps and optimization in small (the sieve's incline study builds on them,
# cmake/sieve.cmake).
# It needs the case layer; until pcsim_sim exists it is skipped, and so are the study
# commands of the pcsim executable (so pcsim still links).
set(_study_cli cpp/cli/cmd_sweep.cpp cpp/cli/cmd_optimize.cpp)
if(NOT TARGET pcsim_sim)
  message(STATUS "pcsim: component study needs pcsim_sim; skipped")
  foreach(f IN LISTS _study_cli)
    set_source_files_properties("${PROJECT_SOURCE_DIR}/${f}" PROPERTIES HEADER_FILE_ONLY TRUE)
  endforeach()
  return()
endif()
pcsim_component(NAME study
  CXX   cpp/study/*.cpp
  LINKS pcsim_sim NLopt::nlopt Threads::Threads)
if(PCSIM_WITH_MPI)
  # Sweeps distribute their points over MPI ranks (cpp/study/cluster.cpp).
  target_link_libraries(pcsim_study PUBLIC MPI::MPI_CXX)
  target_compile_definitions(pcsim_study PUBLIC PCSIM_WITH_MPI)
endif()
# The study tests run on the sieve's case (tests/study/study_fixtures.hpp): they are the
# sieve's until they get a case of their own.
pcsim_boost_tests(DIR tests/study LINKS pcsim_study
  SIEVE test_incline test_optimize test_study_cli test_study_real test_sweep)
pcsim_benchmarks(PREFIX bench_study LINKS pcsim_study SIEVE bench_study)

# The CLI tests call the pcsim executable (defined later; generator expressions resolve at
# generate time). PCSIM_EXE tells a test where it is.
foreach(t test_study_cli)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
  endif()
endforeach()

if(PCSIM_WITH_MPI AND PCSIM_WITH_SIEVE)
  # MPI 2 ranks = 1 job: the same sweep distributed over 2 ranks writes the same sweep.csv as
  # one process (fake runner: tests/study/mpi_sweep_check.cpp), and so does `pcsim sweep`
  # with the real integrator (tests/study/mpi_sweep_cli.cmake).
  # OpenMPI's own allocations still live at exit are reported as leaks under ASan (Debug with
  # MPI on); they are not ours, so leak detection is off for these two tests only.
  set(_mpi_env "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1;ASAN_OPTIONS=detect_leaks=0")
  add_executable(mpi_sweep_check tests/study/mpi_sweep_check.cpp)
  target_link_libraries(mpi_sweep_check PRIVATE pcsim_study pcsim_sieve)
  target_include_directories(mpi_sweep_check PRIVATE "${PROJECT_SOURCE_DIR}/tests/study")
  target_compile_definitions(mpi_sweep_check PRIVATE PCSIM_BINARY_DIR="${CMAKE_BINARY_DIR}")
  add_test(NAME study_mpi_sweep_2ranks
    COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 --oversubscribe
            $<TARGET_FILE:mpi_sweep_check>
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
  add_test(NAME study_mpi_sweep_cli_2ranks
    COMMAND ${CMAKE_COMMAND} -DPCSIM=$<TARGET_FILE:pcsim> -DMPIEXEC=${MPIEXEC_EXECUTABLE}
            -DCASE=${PROJECT_SOURCE_DIR}/cases/sieve_1995.toml
            -DOUT=${CMAKE_BINARY_DIR}/test-scratch/mpi_cli
            -P ${PROJECT_SOURCE_DIR}/tests/study/mpi_sweep_cli.cmake
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
  set_tests_properties(study_mpi_sweep_2ranks study_mpi_sweep_cli_2ranks
    PROPERTIES ENVIRONMENT "${_mpi_env}" LABELS "mpi")
endif()
