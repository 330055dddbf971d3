// Test helper: registers the built-in sieve model with the case layer before any test runs.
#pragma once

#include "sieve/source.hpp"

namespace pcsim::testing {
inline const bool kSieveRegistered = (pcsim::sieve::register_sieve(), true);
}  // namespace pcsim::testing
