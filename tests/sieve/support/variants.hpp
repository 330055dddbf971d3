// The sieve's C++ model forms as variants of the built-in model "sieve" (tests and benchmarks
// only): RunOptions::variant "closed_form" (the paper's (3.4) through the engine's automatic
// differentiation: the path before issue 14, which made the rolling-as-printed references),
// "geometric" (bodies, springs and dampers) and "analytic" (hand-derived M, h, Q). The shipped
// sieve integrates its model file; the tests prove the four equal.
#pragma once

namespace pcsim::sieve::testing {

/// Registers the sieve (register_sieve) and then replaces its model source by one that also
/// offers the C++ variants. Idempotent; call it before loading a case.
void register_sieve_variants();

}  // namespace pcsim::sieve::testing
