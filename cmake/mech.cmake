# Component mech: the principle-of-compatibility engine (models, reactions, ODE/DAE forms).
pcsim_component(NAME mech
  CXX   cpp/mech/*.cpp cpp/mech/models/*.cpp
  LINKS pcsim_huang pcsim_radau)
pcsim_boost_tests(DIR tests/mech LINKS pcsim_mech)
pcsim_benchmarks(PREFIX bench_mech LINKS pcsim_mech)
