// Running a case of any model: simulate, the window extremes of every column refined on the
// dense output, the time series, the summary (the generic keys of model-files.md plus the
// model client's), the output directory written as a whole, and the engineer's report.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "sim/case.hpp"

namespace pcsim::sim {

/// The most time-series rows a run writes; a case asking for more (output.dt against
/// solver.t_end) is refused before any computation, naming output.dt and the row count.
inline constexpr double kMaxOutputRows = 1e7;

struct RunOptions {
  /// Where to write timeseries.csv and summary.json; nullopt writes nothing (sweeps). The
  /// directory is locked for the run and replaced as a whole at its end (common/files.hpp).
  std::optional<std::filesystem::path> out_dir;
  /// Internal (not a case key, not a CLI flag): an equivalent description of the model, passed
  /// to ModelSource::instantiate ("" = the default; the sieve offers "closed_form", "geometric",
  /// "analytic" for the benchmarks and tests).
  std::string variant;
};

/// Runs the case to solver.t_end and returns summary.json's content. Thread-safe: concurrent
/// calls on different cases share nothing. Throws pcsim::InputError for what the case asks that
/// cannot be done (too many rows, an output directory in use), pcsim::NumericalError (with the
/// model time and the reason) if the simulation fails, pcsim::IoError if output cannot be
/// written.
nlohmann::json run_case(const Case& c, const RunOptions& options = {});

/// The engineer's report printed by `pcsim run` (the client's, or the generic one).
std::string human_report(const Case& c, const nlohmann::json& summary);

/// The time-series column names of a case: t, coordinates, <name>_d, R_<name>, outputs,
/// residual_pos, residual_vel, and with contact.switching mode_<name> per switched contact.
std::vector<std::string> timeseries_columns(const Case& c);

/// The unilateral constraints a case switches (contact.switching = true and active), in model
/// order; empty without switching.
std::vector<std::string> switched_contacts(const Case& c);

}  // namespace pcsim::sim
