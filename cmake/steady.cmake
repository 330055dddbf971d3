# Component steady: the periodic steady state directly (Newton shooting on the constraint
# manifold with the monodromy matrix from the variational equations, Floquet stability,
# slow coordinates held at their mean, pseudo-arclength continuation for frequency responses).
# It needs the run layer and the study component (parallel points); until they exist it is
# skipped, and so are `pcsim steady` and `pcsim response` (so pcsim still links).
set(_steady_cli cpp/cli/cmd_steady.cpp cpp/cli/cmd_response.cpp)
if(NOT TARGET pcsim_study)
  message(STATUS "pcsim: component steady needs pcsim_study; skipped")
  foreach(f IN LISTS _steady_cli)
    set_source_files_properties("${PROJECT_SOURCE_DIR}/${f}" PROPERTIES HEADER_FILE_ONLY TRUE)
  endforeach()
  return()
endif()
pcsim_component(NAME steady
  CXX   cpp/steady/*.cpp
  LINKS pcsim_study)
pcsim_boost_tests(DIR tests/steady LINKS pcsim_steady)
pcsim_benchmarks(PREFIX bench_steady LINKS pcsim_steady)

foreach(t test_steady_cli)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
  endif()
endforeach()
