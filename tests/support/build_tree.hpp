// What a test asks of the build it runs in, at run time rather than by macros:
// - binary_dir(): the build tree, from PCSIM_BINARY_DIR (CTest sets it for every test; see
//   pcsim_boost_tests in cmake/pcsim_helpers.cmake). It is not compiled in: a test's command
//   line is then the same in every build tree, so the compiler cache (ccache, in CI) serves the
//   later builds the objects of the Release build;
// - sanitized(), slow_build(): whether pcsim runs under the sanitizers (or the tests at -O0),
//   for the tests that size their work to the build.
#pragma once

#include <dlfcn.h>

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

/// True in a process that runs under AddressSanitizer (the sanitized Debug build links its runtime
/// into every test executable), where pcsim runs many times slower and the tests that size their
/// work take the short version. Asked at run time, not by NDEBUG: CI's sanitized build compiles
/// the tests' own code with the Release build's flags (PCSIM_TESTS_AS_RELEASE).
inline bool sanitized() { return dlsym(RTLD_DEFAULT, "__asan_init") != nullptr; }

/// A build where the tests take their short versions: sanitized, or the tests' code compiled
/// without NDEBUG (a Debug build at -O0).
inline bool slow_build() {
#ifdef NDEBUG
  return sanitized();
#else
  return true;
#endif
}

}  // namespace pcsim_test
