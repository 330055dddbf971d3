# Component sieve: the vibration-sieve model, case files, run/summary/plot logic.
pcsim_component(NAME sieve
  CXX   cpp/sieve/*.cpp
  LINKS pcsim_mech tomlplusplus::tomlplusplus nlohmann_json::nlohmann_json)
pcsim_boost_tests(DIR tests/sieve LINKS pcsim_sieve)
pcsim_benchmarks(PREFIX bench_sieve LINKS pcsim_sieve)
