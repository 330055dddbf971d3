# The pcsim executable: every cpp/cli/*.cpp is compiled in, so each command file registers
# itself (see cpp/cli/commands.hpp). It links the most complete component that exists.
file(GLOB PCSIM_CLI_SOURCES CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/cpp/cli/*.cpp")
set(_pcsim_top)
foreach(c steady study sieve mech radau huang)
  if(TARGET pcsim_${c} AND NOT _pcsim_top)
    set(_pcsim_top pcsim_${c})
  endif()
endforeach()
add_executable(pcsim ${PCSIM_CLI_SOURCES})
target_link_libraries(pcsim PRIVATE ${_pcsim_top} CLI11::CLI11)
target_include_directories(pcsim PRIVATE "${PROJECT_SOURCE_DIR}/cpp")
