# Component radau: 3-stage Radau IIA for K y' = f(t, y), Fortran kernel + bridge + C++ port.
pcsim_component(NAME radau
  FORTRAN fortran/radau*.f
  BRIDGE  bridge/radau*.f90
  CXX     cpp/ode/*.cpp
  LINKS   pcsim_common Eigen3::Eigen LAPACK::LAPACK Threads::Threads)
pcsim_boost_tests(DIR tests/radau LINKS pcsim_radau)
pcsim_benchmarks(PREFIX bench_radau LINKS pcsim_radau)
