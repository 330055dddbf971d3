# Install and export the kernel libraries: find_package(pcsim) + target_link_libraries(app pcsim::radau).
# The static kernel libraries contain Fortran objects, so whoever links them needs the Fortran
# runtime: it is part of their link interface (found where this compiler keeps it), and the
# consumer lists nothing by hand.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
find_library(PCSIM_FORTRAN_RUNTIME NAMES gfortran
             HINTS ${CMAKE_Fortran_IMPLICIT_LINK_DIRECTORIES})
foreach(c radau huang)
  if(PCSIM_FORTRAN_RUNTIME)
    target_link_libraries(pcsim_${c} INTERFACE "$<INSTALL_INTERFACE:${PCSIM_FORTRAN_RUNTIME}>")
  endif()
endforeach()
set_target_properties(pcsim_radau PROPERTIES EXPORT_NAME radau)
set_target_properties(pcsim_huang PROPERTIES EXPORT_NAME huang)
set_target_properties(pcsim_common PROPERTIES EXPORT_NAME common)
install(TARGETS pcsim_common pcsim_huang pcsim_radau EXPORT pcsimTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES bridge/pcsim_kernels.h bridge/pcsim_huang.h bridge/pcsim_radau.h
              bridge/pcsim_ode_status.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pcsim)
install(FILES cpp/common/kernel.hpp cpp/common/error.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pcsim/common)
install(FILES cpp/ode/radau.hpp cpp/ode/status.hpp cpp/ode/radau_port.hpp cpp/ode/radau_lu.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pcsim/ode)
install(FILES cpp/linalg/huang.hpp cpp/linalg/huang_port.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/pcsim/linalg)
install(EXPORT pcsimTargets NAMESPACE pcsim::
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pcsim)
file(WRITE "${CMAKE_BINARY_DIR}/pcsimConfig.cmake.in" [=[
@PACKAGE_INIT@
# pcsim: the Radau IIA and Huang kernels (pcsim::radau, pcsim::huang, pcsim::common).
include(CMakeFindDependencyMacro)
find_dependency(Eigen3 3.3 NO_MODULE)
find_dependency(LAPACK)
find_dependency(Threads)
include("${CMAKE_CURRENT_LIST_DIR}/pcsimTargets.cmake")
]=])
configure_package_config_file("${CMAKE_BINARY_DIR}/pcsimConfig.cmake.in"
  "${CMAKE_BINARY_DIR}/pcsimConfig.cmake" INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pcsim)
write_basic_package_version_file("${CMAKE_BINARY_DIR}/pcsimConfigVersion.cmake"
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_BINARY_DIR}/pcsimConfig.cmake" "${CMAKE_BINARY_DIR}/pcsimConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pcsim)

