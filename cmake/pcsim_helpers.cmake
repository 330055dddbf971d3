# Helpers shared by the component fragments.

# pcsim_component(NAME name FORTRAN globs... BRIDGE globs... CXX globs... LINKS targets...)
# Builds the static library pcsim_<name> from the files matching the globs (CONFIGURE_DEPENDS,
# so a new file is picked up by the next build). Fortran modules go to a per-target directory.
function(pcsim_component)
  cmake_parse_arguments(C "" "NAME" "FORTRAN;BRIDGE;CXX;LINKS" ${ARGN})
  set(srcs)
  foreach(g IN LISTS C_FORTRAN C_BRIDGE C_CXX)
    file(GLOB found CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/${g}")
    list(APPEND srcs ${found})
  endforeach()
  # The module directory must exist even for components without Fortran, since it is on the
  # include path (gfortran warns about missing include directories).
  file(MAKE_DIRECTORY "${CMAKE_BINARY_DIR}/mod/${C_NAME}")
  add_library(pcsim_${C_NAME} STATIC ${srcs})
  set_target_properties(pcsim_${C_NAME} PROPERTIES
    Fortran_MODULE_DIRECTORY "${CMAKE_BINARY_DIR}/mod/${C_NAME}"
    LINKER_LANGUAGE CXX)
  # Source-tree include directories for the build only; an installed component's headers are
  # under include/pcsim (see the install rules in cmake/radau.cmake).
  target_include_directories(pcsim_${C_NAME} PUBLIC
    "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/cpp>" "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/bridge>"
    "$<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/mod/${C_NAME}>" "$<INSTALL_INTERFACE:include/pcsim>")
  target_link_libraries(pcsim_${C_NAME} PUBLIC ${C_LINKS})
endfunction()

# pcsim_boost_tests(DIR tests/linalg LINKS pcsim_huang [LABELS ...])
# Every tests/<dir>/test_*.cpp becomes one Boost.Test executable and one CTest test of the
# same name, run from the source tree root so tests can read cases/ and models/. PCSIM_EXE in
# the test's environment names the pcsim executable, for the tests that run it as a user does
# (a generator expression: the executable is defined in cpp/cli, resolved at generate time).
function(pcsim_boost_tests)
  cmake_parse_arguments(T "" "DIR" "LINKS;LABELS" ${ARGN})
  file(GLOB files CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/${T_DIR}/test_*.cpp")
  foreach(f IN LISTS files)
    get_filename_component(name "${f}" NAME_WE)
    add_executable(${name} "${f}")
    target_link_libraries(${name} PRIVATE ${T_LINKS} Boost::unit_test_framework)
    target_compile_definitions(${name} PRIVATE BOOST_TEST_DYN_LINK
      PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}" PCSIM_BINARY_DIR="${CMAKE_BINARY_DIR}")
    add_test(NAME ${name} COMMAND ${name} --log_level=test_suite --report_level=short
             WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
    set_tests_properties(${name} PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
    if(T_LABELS)
      set_tests_properties(${name} PROPERTIES LABELS "${T_LABELS}")
    endif()
  endforeach()
endfunction()

# pcsim_benchmarks(DIR bench PREFIX bench_huang LINKS ...): bench/<prefix>*.cpp -> executables.
function(pcsim_benchmarks)
  cmake_parse_arguments(B "" "PREFIX" "LINKS" ${ARGN})
  file(GLOB files CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/bench/${B_PREFIX}*.cpp")
  foreach(f IN LISTS files)
    get_filename_component(name "${f}" NAME_WE)
    add_executable(${name} "${f}")
    target_link_libraries(${name} PRIVATE ${B_LINKS})
    target_compile_definitions(${name} PRIVATE PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()
endfunction()
