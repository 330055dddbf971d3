// Test helper: registers the built-in sieve model, with its C++ variants (support/variants.hpp),
// with the case layer before any test runs.
#pragma once

#include "sieve/support/variants.hpp"

namespace pcsim::testing {
inline const bool kSieveRegistered = (pcsim::sieve::testing::register_sieve_variants(), true);
}  // namespace pcsim::testing
