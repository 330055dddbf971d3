# Application sieve: the vibration sieve of the 1995 paper as a client of the case layer (the
# built-in model "sieve", its verdicts, summary keys, report and figures). An application is a
# leaf: nothing below links it, and with -DPCSIM_WITH_SIEVE=OFF everything else builds and
# passes without it. Its commands and registration (cpp/sieve/cli/*.cpp) are compiled into the
# pcsim executable (cmake/app.cmake). It comes after the components it builds on (the case
# layer, the sweep of the studies).
if(NOT PCSIM_WITH_SIEVE)
  message(STATUS "pcsim: the sieve application is off (PCSIM_WITH_SIEVE=OFF)")
  return()
endif()
pcsim_component(NAME sieve
  CXX   cpp/sieve/*.cpp
  LINKS pcsim_sim)
# Its incline study (`pcsim study incline`), built on the generic sweep: a library of its own,
# so that the sieve's model and client do not carry the studies.
pcsim_component(NAME sieve_incline
  CXX   cpp/sieve/incline/*.cpp
  LINKS pcsim_sieve pcsim_study)
list(APPEND PCSIM_APPLICATIONS sieve)
list(APPEND PCSIM_APPLICATION_LIBRARIES pcsim_sieve pcsim_sieve_incline)
foreach(t test_incline test_study_real)
  if(TARGET ${t})
    target_link_libraries(${t} PRIVATE pcsim_sieve_incline)
  endif()
endforeach()
# Tests of other components with test cases of the sieve (#if PCSIM_WITH_SIEVE).
foreach(t test_equilibrium_runup test_steady_derivatives)
  if(TARGET ${t})
    target_link_libraries(${t} PRIVATE pcsim_sieve)
  endif()
endforeach()
# The sieve's C++ model forms (the paper's closed form through AD, the geometric form, the
# hand-derived model) as variants of the built-in sieve, for its tests and benchmarks only: the
# shipped library integrates the model file.
file(GLOB _sieve_support CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/tests/sieve/support/*.cpp")
add_library(pcsim_sieve_testing STATIC ${_sieve_support})
target_link_libraries(pcsim_sieve_testing PUBLIC pcsim_sieve)
target_include_directories(pcsim_sieve_testing PUBLIC "${PROJECT_SOURCE_DIR}/tests")
pcsim_boost_tests(DIR tests/sieve LINKS pcsim_sieve pcsim_sieve_testing LABELS sieve)
pcsim_benchmarks(PREFIX bench_sieve LINKS pcsim_sieve pcsim_sieve_testing)
foreach(t test_modelfile_sieve bench_modelfile bench_steady)
  if(TARGET ${t})
    target_link_libraries(${t} PRIVATE pcsim_sieve_testing)
  endif()
endforeach()

# The CLI tests call the pcsim executable (defined later, in CMakeLists.txt; generator
# expressions resolve at generate time). PCSIM_EXE tells a test where it is.
if(TEST test_sieve_cli)
  set_tests_properties(test_sieve_cli PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
endif()

# The sieve's cases are also case tests (cmake/cases.cmake). Erratum 7: that the printed
# rolling sign reproduces the references made before the erratum, bit for bit, is a Boost test
# (test_sieve_rolling): it needs the C++ closed-form model variant of that path, which is not a
# case key.

# Results independent of the system BLAS's threading and core type (issue 14), on the sieve's
# case.
add_test(NAME blas_independence
  COMMAND ${CMAKE_COMMAND}
    -DPCSIM=$<TARGET_FILE:pcsim> -DCOMPARE=$<TARGET_FILE:case_compare_summary>
    -DCASE=${PROJECT_SOURCE_DIR}/cases/sieve_1995.toml
    -DOUT=${CMAKE_BINARY_DIR}/test-scratch/blas_independence
    -P ${PROJECT_SOURCE_DIR}/tests/sim/blas_independence.cmake)
set_tests_properties(blas_independence PROPERTIES LABELS "sieve")
