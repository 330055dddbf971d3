// The sieve's client of the generic run layer: the working conditions of the paper, contact
// (3.1) R_u > 0 and rolling (3.2) f* = |R_s|/R_u < f (3.3), checked over the whole run with
// their first violation located on the dense output; the window extremes of x, y, theta, R_u and
// f*; the summary keys of architecture.md section 4; the engineer's report.
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "sim/client.hpp"

namespace pcsim::sieve {

/// The sieve client (registered for model "sieve" by register_sieve()).
std::shared_ptr<const sim::Client> make_sieve_client();

/// The summary columns of a sieve sweep.csv, in order (every scalar of summary.json that is a
/// deterministic function of the case, then the two design margins).
const std::vector<std::string>& sieve_sweep_columns();

/// The parameters the paper does not print (sieve-model.md section 5 table), by key, in the
/// order of that table: these are the run's assumptions and are reported as such.
const std::vector<std::string>& unprinted_parameter_keys();

/// The figures of `pcsim plot` for a sieve run (sim::Client::figures).
std::vector<sim::PlotFigure> sieve_figures(const nlohmann::json& summary,
                                           const std::set<std::string>& columns,
                                           const std::string& table);

}  // namespace pcsim::sieve
