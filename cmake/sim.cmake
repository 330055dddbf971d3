# Component sim: case files, runs, summaries and output for any model (the generic layer above
# the engine and the model files; model-specific clients such as the sieve plug into it).
if(NOT TARGET pcsim_mech OR NOT TARGET pcsim_modelfile)
  message(STATUS "pcsim: component sim needs pcsim_mech and pcsim_modelfile; skipped")
  return()
endif()
# The built-in model files, embedded into the library (regenerated when a file changes).
set(PCSIM_EMBEDDED_MODELS sieve_1995 sieve_1995_runup pendulum rolling_disk slider_crank)
set(_embedded_cpp "${CMAKE_BINARY_DIR}/generated/embedded_models.cpp")
set(_embedded_deps)
foreach(m IN LISTS PCSIM_EMBEDDED_MODELS)
  list(APPEND _embedded_deps "${PROJECT_SOURCE_DIR}/models/${m}.toml")
endforeach()
string(REPLACE ";" "," _embedded_list "${PCSIM_EMBEDDED_MODELS}")
add_custom_command(OUTPUT "${_embedded_cpp}"
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DOUT=${_embedded_cpp}
          -DMODELS=${_embedded_list} -P ${PROJECT_SOURCE_DIR}/cmake/embed_models.cmake
  DEPENDS ${_embedded_deps} ${PROJECT_SOURCE_DIR}/cmake/embed_models.cmake
  COMMENT "embedding the built-in model files")
# Their compiled models, derived at build time (start-up then skips the symbolic derivation).
add_executable(precompile_models tools/precompile_models.cpp)
target_link_libraries(precompile_models PRIVATE pcsim_modelfile)
set(_tapes_cpp "${CMAKE_BINARY_DIR}/generated/embedded_tapes.cpp")
add_custom_command(OUTPUT "${_tapes_cpp}"
  COMMAND ${CMAKE_COMMAND} -E env ASAN_OPTIONS=detect_leaks=0 $<TARGET_FILE:precompile_models> "${_tapes_cpp}" ${_embedded_deps}
  DEPENDS precompile_models ${_embedded_deps}
  COMMENT "deriving the built-in model files")
pcsim_component(NAME sim
  CXX   cpp/sim/*.cpp
  LINKS pcsim_modelfile pcsim_mech tomlplusplus::tomlplusplus nlohmann_json::nlohmann_json)
target_sources(pcsim_sim PRIVATE "${_embedded_cpp}" "${_tapes_cpp}")
pcsim_boost_tests(DIR tests/sim LINKS pcsim_sim)

# The CLI tests call the pcsim executable (defined later; generator expressions resolve at
# generate time). PCSIM_EXE tells a test where it is.
foreach(t test_abuse_cli test_files_cli test_files_fuzz test_runs_trust test_hostile_model_cli test_steady_fuzz)
  if(TEST ${t})
    set_tests_properties(${t} PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
  endif()
endforeach()
