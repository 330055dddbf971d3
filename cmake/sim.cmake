# Component sim: case files, runs, summaries and output for any model (the generic layer above
# the engine; model-specific clients such as the sieve plug into it).
if(NOT TARGET pcsim_mech)
  message(STATUS "pcsim: component sim needs pcsim_mech; skipped")
  return()
endif()
pcsim_component(NAME sim
  CXX   cpp/sim/*.cpp
  LINKS pcsim_mech tomlplusplus::tomlplusplus nlohmann_json::nlohmann_json)
pcsim_boost_tests(DIR tests/sim LINKS pcsim_sim)

# The CLI tests call the pcsim executable (defined later; generator expressions resolve at
# generate time). PCSIM_EXE tells a test where it is.
if(TEST test_abuse_cli)
  set_tests_properties(test_abuse_cli PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
endif()
