# Component lcp: linear complementarity problems (issue 12) solved by Siconos numerics through
# a plugin that pcsim dlopen()s on first use (cpp/lcp/lcp.hpp): Siconos links OpenBLAS, and a
# run that never needs an LCP must not load it (pcsim itself is pinned to the reference
# BLAS/LAPACK, see CMakeLists.txt). Without Siconos the plugin is not built and solve_lcp()
# reports that it cannot load it.
pcsim_component(NAME lcp
  CXX   cpp/lcp/*.cpp
  LINKS Eigen3::Eigen ${CMAKE_DL_LIBS})
find_path(PCSIM_SICONOS_INCLUDE_DIR siconos/numerics/LCP_Solvers.h)
find_library(PCSIM_SICONOS_NUMERICS_LIBRARY siconos_numerics)
if(PCSIM_SICONOS_INCLUDE_DIR AND PCSIM_SICONOS_NUMERICS_LIBRARY)
  add_library(pcsim_lcp_siconos MODULE cpp/lcp/siconos_plugin.c)
  set_target_properties(pcsim_lcp_siconos PROPERTIES
    PREFIX "" OUTPUT_NAME pcsim_lcp_siconos C_VISIBILITY_PRESET hidden
    LIBRARY_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}")
  target_include_directories(pcsim_lcp_siconos PRIVATE
    "${PCSIM_SICONOS_INCLUDE_DIR}" "${PCSIM_SICONOS_INCLUDE_DIR}/siconos"
    "${PROJECT_SOURCE_DIR}/cpp/lcp")
  target_link_libraries(pcsim_lcp_siconos PRIVATE "${PCSIM_SICONOS_NUMERICS_LIBRARY}")
  # The build tree's plugin, tried after the one next to the executable.
  target_compile_definitions(pcsim_lcp PRIVATE
    PCSIM_LCP_PLUGIN_BUILD_PATH="$<TARGET_FILE:pcsim_lcp_siconos>")
  add_dependencies(pcsim_lcp pcsim_lcp_siconos)
  message(STATUS "pcsim: Siconos numerics found (${PCSIM_SICONOS_NUMERICS_LIBRARY}); LCP plugin built")
else()
  message(STATUS "pcsim: Siconos numerics not found; the LCP plugin is not built (install libsiconos-numerics-dev)")
endif()
pcsim_boost_tests(DIR tests/lcp LINKS pcsim_lcp)
# Siconos numerics 4.4's enumerative LCP solver leaks its 32-byte enumeration state (enum_init)
# on every call; test_lcp_siconos (which does not link modelfile, whose LeakSanitizer hook
# suppresses it in every other program) gets the suppression from a file.
if(TEST test_lcp_siconos)
  set_tests_properties(test_lcp_siconos PROPERTIES ENVIRONMENT
    "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lcp/lsan_siconos.supp:print_suppressions=0")
endif()
