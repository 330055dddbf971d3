# The case regression harness: every case in cases/ with a stored reference summary is a test.
# It runs the case through `pcsim run` and compares summary.json with
# cases/reference/<case>.summary.json to the number of significant digits stated in the
# reference file's "compare" entry (tests/sieve/compare_summary.cpp). A case is a test only if
# its model is built: the sieve's cases (model = "sieve", or no model, the sieve being the
# default model) only with PCSIM_WITH_SIEVE.
add_executable(case_compare_summary tests/sieve/compare_summary.cpp)
target_link_libraries(case_compare_summary PRIVATE nlohmann_json::nlohmann_json)
file(GLOB _case_refs CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/cases/reference/*.summary.json")
foreach(ref IN LISTS _case_refs)
  get_filename_component(_name "${ref}" NAME)
  string(REPLACE ".summary.json" "" _case "${_name}")
  set(_case_file "${PROJECT_SOURCE_DIR}/cases/${_case}.toml")
  file(READ "${_case_file}" _text)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${_case_file}")
  set(_labels case)
  if(_text MATCHES "(^|\n)[ \t]*model[ \t]*=[ \t]*\"sieve\"" OR
     NOT _text MATCHES "(^|\n)[ \t]*(model[ \t]*=|\\[model[].])")
    if(NOT PCSIM_WITH_SIEVE)
      continue()
    endif()
    list(APPEND _labels sieve)
  endif()
  add_test(NAME case_${_case}
    COMMAND ${CMAKE_COMMAND}
      -DPCSIM=$<TARGET_FILE:pcsim> -DCOMPARE=$<TARGET_FILE:case_compare_summary>
      -DCASE=${_case_file} -DREFERENCE=${ref}
      -DOUT=${CMAKE_BINARY_DIR}/case_out/${_case}
      -P ${PROJECT_SOURCE_DIR}/tests/sieve/run_case.cmake)
  set_tests_properties(case_${_case} PROPERTIES LABELS "${_labels}")
endforeach()
