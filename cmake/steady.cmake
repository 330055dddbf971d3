# Component steady: the periodic steady state directly (Newton shooting on the constraint
# manifold with the monodromy matrix from the variational equations, Floquet stability,
# slow coordinates held at their mean, pseudo-arclength continuation for frequency responses).
# It needs the case layer; until it exists it is skipped, and so are `pcsim steady` and
# `pcsim response` (so pcsim still links).
set(_steady_cli cpp/cli/cmd_steady.cpp cpp/cli/cmd_response.cpp)
if(NOT TARGET pcsim_sim)
  message(STATUS "pcsim: component steady needs pcsim_sim; skipped")
  foreach(f IN LISTS _steady_cli)
    set_source_files_properties("${PROJECT_SOURCE_DIR}/${f}" PROPERTIES HEADER_FILE_ONLY TRUE)
  endforeach()
  return()
endif()
pcsim_component(NAME steady
  CXX   cpp/steady/*.cpp
  LINKS pcsim_sim Threads::Threads)
# The tests and the benchmark of the sieve's steady state are the sieve's (and so are the sieve
# test cases of test_equilibrium_runup and test_steady_derivatives: #if PCSIM_WITH_SIEVE, they
# link the sieve, cmake/sieve.cmake).
pcsim_boost_tests(DIR tests/steady LINKS pcsim_steady
  SIEVE test_steady_sieve test_steady_cli)
pcsim_benchmarks(PREFIX bench_steady LINKS pcsim_steady SIEVE bench_steady)

foreach(t test_steady_cli)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
  endif()
endforeach()
