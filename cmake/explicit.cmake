# Component explicit: the explicit Runge-Kutta pair Dormand-Prince 8(5,3) (fortran/explicit_rk.f,
# its bridge and the C++ port in cpp/ode/), and ode_integrate (cpp/ode/integrate.hpp), which
# selects Radau, the explicit pair, or both (auto). The sources are part of pcsim_radau, the
# ODE library (its cpp/ode/*.cpp glob already takes the C++ files), so the engine links one
# library for every method.
if(TARGET pcsim_radau)
  target_sources(pcsim_radau PRIVATE
    "${PROJECT_SOURCE_DIR}/fortran/explicit_rk.f"
    "${PROJECT_SOURCE_DIR}/bridge/explicit_rk_bridge.f90")
  pcsim_boost_tests(DIR tests/explicit LINKS pcsim_radau)
  pcsim_benchmarks(PREFIX bench_explicit LINKS pcsim_radau)
endif()
