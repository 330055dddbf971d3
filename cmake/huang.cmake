# Component huang: the modified Huang (ABS) solver, Fortran kernel + bridge + C++ port.
pcsim_component(NAME common CXX cpp/common/*.cpp LINKS Eigen3::Eigen)
pcsim_component(NAME huang
  FORTRAN fortran/huang*.f
  BRIDGE  bridge/huang*.f90
  CXX     cpp/linalg/*.cpp
  LINKS   pcsim_common Eigen3::Eigen LAPACK::LAPACK)
pcsim_boost_tests(DIR tests/huang LINKS pcsim_huang LAPACK::LAPACK)
pcsim_benchmarks(PREFIX bench_huang LINKS pcsim_huang)
