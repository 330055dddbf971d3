# Helpers shared by the folders' CMakeLists.txt.

# pcsim_component(NAME name FORTRAN globs... BRIDGE globs... CXX globs... LINKS targets...)
# Builds the static library (shared with PCSIM_SHARED_LIBS, except the installed kernels)
# pcsim_<name> from the files matching the globs (relative to the source tree's root;
# CONFIGURE_DEPENDS, so a new file is picked up by the next build). Fortran modules go to a
# per-target directory.
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
  set(type STATIC)
  if(PCSIM_SHARED_LIBS AND NOT C_NAME MATCHES "^(common|huang|radau)$")
    set(type SHARED)
  endif()
  add_library(pcsim_${C_NAME} ${type} ${srcs})
  set_target_properties(pcsim_${C_NAME} PROPERTIES
    Fortran_MODULE_DIRECTORY "${CMAKE_BINARY_DIR}/mod/${C_NAME}"
    LINKER_LANGUAGE CXX)
  # Source-tree include directories for the build only; an installed component's headers are
  # under include/pcsim (see cmake/install.cmake).
  target_include_directories(pcsim_${C_NAME} PUBLIC
    "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/cpp>" "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/bridge>"
    "$<BUILD_INTERFACE:${CMAKE_BINARY_DIR}/mod/${C_NAME}>" "$<INSTALL_INTERFACE:include/pcsim>")
  target_link_libraries(pcsim_${C_NAME} PUBLIC ${C_LINKS})
endfunction()

# pcsim_application(NAME name LINKS targets... [LIBRARIES more...])
# An application (a leaf above the case layer): the library pcsim_<name> from cpp/<name>/*.cpp,
# and its commands, cpp/<name>/cli/*.cpp, compiled into the pcsim executable, where each
# registers itself (cpp/cli/commands.hpp). LIBRARIES names further libraries of the application
# that the executable links (e.g. the sieve's incline study). A new application is its folder
# and one add_subdirectory line in the top CMakeLists.txt.
function(pcsim_application)
  cmake_parse_arguments(A "" "NAME" "LINKS;LIBRARIES" ${ARGN})
  pcsim_component(NAME ${A_NAME} CXX cpp/${A_NAME}/*.cpp LINKS ${A_LINKS})
  file(GLOB commands CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/cpp/${A_NAME}/cli/*.cpp")
  set_property(GLOBAL APPEND PROPERTY PCSIM_COMMAND_SOURCES ${commands})
  set_property(GLOBAL APPEND PROPERTY PCSIM_APPLICATION_LIBRARIES pcsim_${A_NAME} ${A_LIBRARIES})
endfunction()

# pcsim_boost_tests(DIR tests/linalg LINKS pcsim_huang [LABELS ...] [SIEVE test_names...])
# Every tests/<dir>/test_*.cpp becomes one Boost.Test executable and one CTest test of the
# same name, run from the source tree root so tests can read cases/ and models/. PCSIM_EXE in
# the test's environment names the pcsim executable, for the tests that run it as a user does
# (a generator expression: the executable is defined in cpp/cli, resolved at generate time), and
# PCSIM_BINARY_DIR the build tree (tests/support/build_tree.hpp reads it).
# The tests named under SIEVE are the sieve's (they need its model, client or C++ forms): they
# also link pcsim_sieve, carry the label "sieve", and exist only with PCSIM_WITH_SIEVE. A test
# whose source names PCSIM_WITH_SIEVE sees it as 1 or 0: a test case of another test that runs a
# sieve case through the pcsim executable is the sieve's by the decorator
# `* boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()` (skipped in a build without it); one that
# calls the sieve's code is compiled only #if PCSIM_WITH_SIEVE (its test links the sieve then).
# Only those tests get the definition, and nothing on a test's command line names the build tree:
# the other tests then compile to the same command line in every build tree, which the compiler
# cache (CI) needs to serve one build's objects to another.
function(pcsim_boost_tests)
  cmake_parse_arguments(T "" "DIR" "LINKS;LABELS;SIEVE" ${ARGN})
  file(GLOB files CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/${T_DIR}/test_*.cpp")
  foreach(f IN LISTS files)
    get_filename_component(name "${f}" NAME_WE)
    set(links ${T_LINKS})
    set(labels ${T_LABELS})
    if(name IN_LIST T_SIEVE)
      if(NOT PCSIM_WITH_SIEVE)
        continue()
      endif()
      list(APPEND links pcsim_sieve)
      list(APPEND labels sieve)
    endif()
    add_executable(${name} "${f}")
    target_link_libraries(${name} PRIVATE ${links} Boost::unit_test_framework)
    target_compile_definitions(${name} PRIVATE BOOST_TEST_DYN_LINK
      PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
    file(READ "${f}" source)
    string(FIND "${source}" "PCSIM_WITH_SIEVE" mentions_sieve)
    if(NOT mentions_sieve EQUAL -1)
      target_compile_definitions(${name} PRIVATE PCSIM_WITH_SIEVE=$<BOOL:${PCSIM_WITH_SIEVE}>)
    endif()
    add_test(NAME ${name} COMMAND ${name} --log_level=test_suite --report_level=short
             WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
    set_tests_properties(${name} PROPERTIES
      ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>;PCSIM_BINARY_DIR=${CMAKE_BINARY_DIR}")
    if(labels)
      set_tests_properties(${name} PROPERTIES LABELS "${labels}")
    endif()
  endforeach()
endfunction()

# pcsim_benchmarks(PREFIX bench_huang LINKS ... [SIEVE names...]):
# bench/<prefix>*.cpp -> executables; those named under SIEVE need the sieve (as for tests).
function(pcsim_benchmarks)
  cmake_parse_arguments(B "" "PREFIX" "LINKS;SIEVE" ${ARGN})
  file(GLOB files CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/bench/${B_PREFIX}*.cpp")
  foreach(f IN LISTS files)
    get_filename_component(name "${f}" NAME_WE)
    set(links ${B_LINKS})
    if(name IN_LIST B_SIEVE)
      if(NOT PCSIM_WITH_SIEVE)
        continue()
      endif()
      list(APPEND links pcsim_sieve)
    endif()
    add_executable(${name} "${f}")
    target_link_libraries(${name} PRIVATE ${links})
    target_compile_definitions(${name} PRIVATE PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endforeach()
endfunction()
