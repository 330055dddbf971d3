# The switching simulation's validation (issue 12): contact problems with exact solutions,
# energy balances, the two reaction formulations, the LCP path and the sieve after losing
# contact. The engine itself is part of mech (cpp/mech/contacts/), the LCP plugin of lcp.
if(NOT TARGET pcsim_sieve)
  return()
endif()
pcsim_boost_tests(DIR tests/switching LINKS pcsim_sieve)
# The CLI tests call the pcsim executable (defined later; generator expressions resolve at
# generate time).
foreach(_t test_switching_cli test_switching_openblas_settings)
  if(TEST ${_t})
    set_tests_properties(${_t} PROPERTIES ENVIRONMENT "PCSIM_EXE=$<TARGET_FILE:pcsim>")
  endif()
endforeach()
