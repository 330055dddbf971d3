// libFuzzer entry point of the case-file fuzz target (scripts/fuzz.sh builds it with clang and
// -fsanitize=fuzzer,address,undefined); a defect aborts so libFuzzer keeps the input.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "case_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string what;
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (pcsim::testing::fuzz_case_input(text, &what) == pcsim::testing::FuzzOutcome::defect) {
    std::fprintf(stderr, "defect: %s\n", what.c_str());
    std::abort();
  }
  return 0;
}
