# Component huang: the modified Huang (ABS) solver, Fortran kernel + bridge + C++ port.
pcsim_component(NAME common CXX cpp/common/*.cpp LINKS Eigen3::Eigen)
# The build's version string (project version + git commit), regenerated at every build.
set(_pcsim_version_cpp "${CMAKE_BINARY_DIR}/generated/pcsim_version.cpp")
add_custom_target(pcsim_version_source
  COMMAND ${CMAKE_COMMAND} -DVERSION=${PROJECT_VERSION} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
          -DOUT=${_pcsim_version_cpp} -P ${PROJECT_SOURCE_DIR}/cmake/version.cmake
  BYPRODUCTS ${_pcsim_version_cpp}
  COMMENT "pcsim version string")
execute_process(COMMAND ${CMAKE_COMMAND} -DVERSION=${PROJECT_VERSION} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
                -DOUT=${_pcsim_version_cpp} -P ${PROJECT_SOURCE_DIR}/cmake/version.cmake)
target_sources(pcsim_common PRIVATE ${_pcsim_version_cpp})
add_dependencies(pcsim_common pcsim_version_source)
pcsim_component(NAME huang
  FORTRAN fortran/huang*.f
  BRIDGE  bridge/huang*.f90
  CXX     cpp/linalg/*.cpp
  LINKS   pcsim_common Eigen3::Eigen LAPACK::LAPACK)
pcsim_boost_tests(DIR tests/huang LINKS pcsim_huang LAPACK::LAPACK)
pcsim_benchmarks(PREFIX bench_huang LINKS pcsim_huang)

# Fortran test driver: calls the kernels directly, self-checks, and writes its inputs and
# results for test_huang_driver (which compares C++ through the bridge and the port to them).
if(TARGET pcsim_huang)
  add_executable(huang_driver tests/huang/huang_driver.f90)
  target_link_libraries(huang_driver PRIVATE pcsim_huang LAPACK::LAPACK)
  set_target_properties(huang_driver PROPERTIES LINKER_LANGUAGE Fortran
    Fortran_MODULE_DIRECTORY "${CMAKE_BINARY_DIR}/mod/huang_driver")
  add_test(NAME huang_driver
           COMMAND huang_driver "${CMAKE_BINARY_DIR}/huang_driver_results.txt")
  set_tests_properties(huang_driver PROPERTIES FIXTURES_SETUP huang_driver_results)
  if(TEST test_huang_driver)
    set_tests_properties(test_huang_driver PROPERTIES FIXTURES_REQUIRED huang_driver_results)
  endif()
endif()
