// The sieve as a hand-derived mech::Model: M, h and Q of the paper's closed form written out
// (partial derivatives of (3.4) by hand), no automatic differentiation. It is the fast model
// `pcsim run` integrates; tests prove it equal to the two AD-derived forms of model.hpp.
#pragma once

#include <memory>

#include "mech/model.hpp"
#include "sieve/support/model.hpp"

namespace pcsim::sieve {

/// The closed-form sieve with analytic M, h, Q and constant constraint rows (contact, rolling,
/// rolling_velocity, lock_theta in that order, as in SieveCommon).
std::shared_ptr<const mech::Model> make_analytic_sieve_model(const SieveCommon& common);

}  // namespace pcsim::sieve
