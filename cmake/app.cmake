# The pcsim executable: every cpp/cli/*.cpp is compiled in, so each command file registers
# itself (see cpp/cli/commands.hpp); so is every cpp/<application>/cli/*.cpp of the applications
# that are built (PCSIM_APPLICATIONS, appended to by their fragments with their libraries,
# PCSIM_APPLICATION_LIBRARIES, e.g. cmake/sieve.cmake), which registers the application and its
# commands. It links the studies, the steady state and
# those applications (or, in a partial build, the most complete component that exists).
file(GLOB PCSIM_CLI_SOURCES CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/cpp/cli/*.cpp")
foreach(app IN LISTS PCSIM_APPLICATIONS)
  file(GLOB _app_cli CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/cpp/${app}/cli/*.cpp")
  list(APPEND PCSIM_CLI_SOURCES ${_app_cli})
endforeach()
set(_pcsim_links ${PCSIM_APPLICATION_LIBRARIES})
foreach(c steady study)
  if(TARGET pcsim_${c})
    list(APPEND _pcsim_links pcsim_${c})
  endif()
endforeach()
foreach(c sim mech radau huang)
  if(TARGET pcsim_${c} AND NOT _pcsim_links)
    list(APPEND _pcsim_links pcsim_${c})
  endif()
endforeach()
add_executable(pcsim ${PCSIM_CLI_SOURCES})
target_link_libraries(pcsim PRIVATE ${_pcsim_links} CLI11::CLI11)
target_include_directories(pcsim PRIVATE "${PROJECT_SOURCE_DIR}/cpp")
