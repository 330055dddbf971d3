# Component study: sweeps, the incline study, optimization in small.
pcsim_component(NAME study
  CXX   cpp/study/*.cpp
  LINKS pcsim_sieve NLopt::nlopt_cxx Threads::Threads)
pcsim_boost_tests(DIR tests/study LINKS pcsim_study)
pcsim_benchmarks(PREFIX bench_study LINKS pcsim_study)
