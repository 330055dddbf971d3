// The build tree a test runs from, read at run time from PCSIM_BINARY_DIR (CTest sets it for every
// test; see pcsim_boost_tests in cmake/pcsim_helpers.cmake). It is not compiled in: a test's
// command line is then the same in every build tree, so the compiler cache (ccache, in CI) serves
// the later builds the objects of the Release build.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace pcsim_test {

/// The build tree (PCSIM_BINARY_DIR); throws if the test was not started by CTest.
inline std::filesystem::path binary_dir() {
  const char* d = std::getenv("PCSIM_BINARY_DIR");
  if (d == nullptr || *d == '\0') {
    throw std::runtime_error("PCSIM_BINARY_DIR is not set: run the tests through ctest "
                             "(or set it to the build tree)");
  }
  return std::filesystem::path(d);
}

}  // namespace pcsim_test
