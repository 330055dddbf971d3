// The sieve's C++ model forms as variants of the built-in model "sieve" (tests and benchmarks
// only): RunOptions::variant "closed_form" (the paper's (3.4) through the engine's automatic
// differentiation: the path before issue 14, which made the rolling-as-printed references),
// "geometric" (bodies, springs and dampers) and "analytic" (hand-derived M, h, Q). The shipped
// sieve integrates its model file; the tests prove the four equal.
#pragma once

#include "sim/run.hpp"

namespace pcsim::sieve::testing {

/// Registers the sieve (register_sieve) and then replaces its model source by one that also
/// offers the C++ variants. Idempotent; call it before loading a case.
void register_sieve_variants();

/// The path before issue 14, on which the rolling-as-printed references were made: the C++
/// closed form (variant "closed_form") and the engine's dense compatibility solve with the drift
/// projection after every step. With the case keys solver.method = "radau" and
/// solver.linear_algebra = "lapack" (LAPACK's LU on the full Newton system), it reproduces
/// those references bit for bit.
inline sim::RunOptions path_before_issue_14() {
  sim::RunOptions o;
  o.variant = "closed_form";
  o.engine = [](mech::SimulationOptions& so) {
    so.reaction_method = mech::ReactionMethod::compatibility;
    so.project_every_step = true;
  };
  return o;
}

}  // namespace pcsim::sieve::testing
