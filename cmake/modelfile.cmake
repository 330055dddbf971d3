# Component modelfile: mechanical systems described in TOML model files (no compilation):
# expressions parsed and differentiated symbolically with GiNaC, evaluated from a flat tape.
# It needs the mechanics engine; until pcsim_mech exists it is skipped.
if(NOT TARGET pcsim_mech)
  message(STATUS "pcsim: component modelfile needs pcsim_mech; skipped")
  return()
endif()
find_package(PkgConfig REQUIRED)
pkg_check_modules(GINAC REQUIRED IMPORTED_TARGET ginac)
pcsim_component(NAME modelfile
  CXX   cpp/modelfile/*.cpp
  LINKS pcsim_mech PkgConfig::GINAC tomlplusplus::tomlplusplus)
# The sieve comparisons (test and benchmark) also need the C++ sieve, a later component
# (target names resolve at generate time).
pcsim_boost_tests(DIR tests/modelfile LINKS pcsim_modelfile SIEVE test_modelfile_sieve)
pcsim_benchmarks(PREFIX bench_modelfile LINKS pcsim_modelfile SIEVE bench_modelfile)

# The LeakSanitizer suppressions for CLN/GiNaC (cpp/modelfile/expression.cpp) must be in every
# sanitized program that links them, also those that never call the parser (the built-in models
# are precompiled): pull the defining object in by naming the symbol as undefined.
if(PCSIM_SANITIZE)
  target_link_options(pcsim_modelfile INTERFACE
    "$<$<CONFIG:Debug>:LINKER:--undefined=__lsan_default_suppressions>"
    "$<$<CONFIG:Debug>:LINKER:--undefined=__lsan_default_options>")
endif()

# The evaluation-order test also runs the pcsim executable (defined later; generator
# expressions resolve at generate time).
if(TEST test_modelfile_evaluation_order)
  set_tests_properties(test_modelfile_evaluation_order PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
endif()
