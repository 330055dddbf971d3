// Running a sieve case: simulate, compute the contracted summary, write the output files.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "sieve/case.hpp"
#include "sieve/model.hpp"

namespace pcsim::sieve {

struct RunOptions {
  /// Where to write timeseries.csv and summary.json; nullopt writes nothing (sweeps).
  /// Files are written to a temporary name and renamed, so a failed run leaves none.
  std::optional<std::filesystem::path> out_dir;
  /// Internal (not a case key, not a CLI flag): which equivalent model description is
  /// integrated. The default is the paper's closed form (3.4) with M, h, Q derived by the
  /// engine's automatic differentiation (issue 4); `analytic` (hand-derived, verified against
  /// the AD forms by the tests) is an opt-in fast path for the C++ API and the benchmarks.
  ModelForm model_form = ModelForm::closed_form;
};

/// Runs the case to solver.t_end and returns summary.json's content (architecture.md section
/// 4: case, model, kernel, form, t_end, window, stats, amplitude, theta_mean, R_u_min, R_u_max,
/// R_u_min_over_weight, fstar_max, contact_kept, rolling_kept, first_violation,
/// constraint_residual_max, q_end, plus "assumptions" and margins). Thread-safe: concurrent
/// calls on different cases share nothing. Throws pcsim::NumericalError (with the model time
/// and the reason) if the integration fails.
nlohmann::json run_case(const Case& c, const RunOptions& options = {});

/// The engineer's report printed by `pcsim run` (assumptions, max |theta|, the contact margin
/// min R_u/(m2 g), the rolling margin 1 - max f*/f, which of (3.1)/(3.2) is closer to
/// violation, verdicts, solver statistics).
std::string human_report(const Case& c, const nlohmann::json& summary);

}  // namespace pcsim::sieve
