# The case-file fuzz target (tests/fuzz): a deterministic mutation harness run by CTest for a
# bounded time (10 s in Release, 60 s in Debug, where the sanitizers watch), and, with
# -DPCSIM_FUZZ=ON and clang, a libFuzzer binary for hours of coverage-guided fuzzing
# (scripts/fuzz.sh).
# With the sieve built, its cases are fuzzed too.
if(NOT TARGET pcsim_sim)
  return()
endif()
add_library(pcsim_case_fuzz STATIC tests/fuzz/case_fuzz.cpp)
target_link_libraries(pcsim_case_fuzz PUBLIC pcsim_sim pcsim_modelfile)
target_compile_definitions(pcsim_case_fuzz PRIVATE PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
if(TARGET pcsim_sieve)
  target_link_libraries(pcsim_case_fuzz PUBLIC pcsim_sieve)
  target_compile_definitions(pcsim_case_fuzz PRIVATE PCSIM_WITH_SIEVE)
endif()
add_executable(fuzz_cases tests/fuzz/fuzz_cases.cpp)
target_link_libraries(fuzz_cases PRIVATE pcsim_case_fuzz)
target_compile_definitions(fuzz_cases PRIVATE PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
if(CMAKE_BUILD_TYPE STREQUAL "Debug")
  set(_fuzz_seconds 60)
else()
  set(_fuzz_seconds 10)
endif()
add_test(NAME fuzz_cases COMMAND fuzz_cases --seconds ${_fuzz_seconds} --seed 1995
         WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
set_tests_properties(fuzz_cases PROPERTIES LABELS "fuzz" TIMEOUT 600)

# The model-file and added-constraint harness (issue 19): hostile expressions, names and sizes
# in inline models and [constraints.added]; each input must end in under 4 s (40 s under the
# sanitizers; the largest legal models take ~1.6 s on the shared 2-core machine) and the process
# under 2 GB. 10 s in Release, 60 s in Debug.
if(TARGET pcsim_modelfile)
  add_executable(fuzz_models tests/fuzz/fuzz_models.cpp)
  target_link_libraries(fuzz_models PRIVATE pcsim_case_fuzz)
  target_compile_definitions(fuzz_models PRIVATE PCSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  if(CMAKE_BUILD_TYPE STREQUAL "Debug")
    set(_fuzz_input_seconds 40)
  else()
    set(_fuzz_input_seconds 4)
  endif()
  add_test(NAME fuzz_models COMMAND fuzz_models --seconds ${_fuzz_seconds} --seed 19
           --input-seconds ${_fuzz_input_seconds}
           WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}")
  set_tests_properties(fuzz_models PROPERTIES LABELS "fuzz" TIMEOUT 600)
endif()

if(PCSIM_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PCSIM_FUZZ needs clang (CXX=clang++); see scripts/fuzz.sh")
  endif()
  add_executable(fuzz_cases_libfuzzer tests/fuzz/libfuzzer_target.cpp)
  target_link_libraries(fuzz_cases_libfuzzer PRIVATE pcsim_case_fuzz)
  target_compile_options(fuzz_cases_libfuzzer PRIVATE -fsanitize=fuzzer)
  target_link_options(fuzz_cases_libfuzzer PRIVATE -fsanitize=fuzzer)
endif()
