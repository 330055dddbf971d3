# Component sieve: the vibration-sieve model, case files, run/summary/plot logic.
# It needs the mechanics engine; until pcsim_mech exists it is skipped (so pcsim still links).
if(NOT TARGET pcsim_sim)
  message(STATUS "pcsim: component sieve needs pcsim_sim; skipped")
  return()
endif()
pcsim_component(NAME sieve
  CXX   cpp/sieve/*.cpp
  LINKS pcsim_sim)
pcsim_boost_tests(DIR tests/sieve LINKS pcsim_sieve)
pcsim_benchmarks(PREFIX bench_sieve LINKS pcsim_sieve)

# The CLI tests call the pcsim executable (defined later, in CMakeLists.txt; generator
# expressions resolve at generate time). PCSIM_EXE tells a test where it is.
if(TEST test_sieve_cli)
  set_tests_properties(test_sieve_cli PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
endif()

# Every case in cases/ with a stored reference summary is a test: run it through `pcsim run`
# and compare summary.json with cases/reference/<case>.summary.json to the number of
# significant digits stated in the reference file's "compare" entry
# (tests/sieve/compare_summary.cpp).
add_executable(sieve_compare_summary tests/sieve/compare_summary.cpp)
target_link_libraries(sieve_compare_summary PRIVATE nlohmann_json::nlohmann_json)
file(GLOB _sieve_refs CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/cases/reference/*.summary.json")
foreach(ref IN LISTS _sieve_refs)
  get_filename_component(_name "${ref}" NAME)
  string(REPLACE ".summary.json" "" _case "${_name}")
  add_test(NAME case_${_case}
    COMMAND ${CMAKE_COMMAND}
      -DPCSIM=$<TARGET_FILE:pcsim> -DCOMPARE=$<TARGET_FILE:sieve_compare_summary>
      -DCASE=${PROJECT_SOURCE_DIR}/cases/${_case}.toml -DREFERENCE=${ref}
      -DOUT=${CMAKE_BINARY_DIR}/case_out/${_case}
      -P ${PROJECT_SOURCE_DIR}/tests/sieve/run_case.cmake)
  set_tests_properties(case_${_case} PROPERTIES LABELS "case")
endforeach()
# Erratum 7: that the printed rolling sign reproduces the references made before the erratum,
# bit for bit, is a Boost test (test_sieve_rolling): it needs the C++ closed-form model variant
# of that path, which is not a case key.

# Results independent of the system BLAS's threading and core type (issue 14).
add_test(NAME blas_independence
  COMMAND ${CMAKE_COMMAND}
    -DPCSIM=$<TARGET_FILE:pcsim> -DCOMPARE=$<TARGET_FILE:sieve_compare_summary>
    -DCASE=${PROJECT_SOURCE_DIR}/cases/sieve_1995.toml
    -DOUT=${CMAKE_BINARY_DIR}/test-scratch/blas_independence
    -P ${PROJECT_SOURCE_DIR}/tests/sim/blas_independence.cmake)
