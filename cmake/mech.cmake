# Component mech: the principle-of-compatibility engine (models, reactions, ODE/DAE forms).
# It needs both kernels; until they exist it is skipped (so pcsim still links).
if(NOT TARGET pcsim_huang OR NOT TARGET pcsim_radau)
  message(STATUS "pcsim: component mech needs pcsim_huang and pcsim_radau; skipped")
  return()
endif()
pcsim_component(NAME mech
  CXX   cpp/mech/*.cpp cpp/mech/contacts/*.cpp cpp/mech/models/*.cpp
  LINKS pcsim_huang pcsim_radau pcsim_lcp)
pcsim_boost_tests(DIR tests/mech LINKS pcsim_mech)
pcsim_benchmarks(PREFIX bench_mech LINKS pcsim_mech)
