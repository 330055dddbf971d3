// The typed result of one run (run_case): what summary.json says, as fields. summary.json is
// to_json(result), written at the edge; the report, the CLI and the sweep table read the fields.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pcsim::sim {

/// A column's extremes over the summary window (NaN where the window saw no value).
struct ColumnExtremes {
  double min = 0.0, max = 0.0;
  double t_min = 0.0, t_max = 0.0;  ///< s, when they occur
  double amplitude() const { return 0.5 * (max - min); }  ///< half the peak-to-peak
};

/// The integrator's counters of a run.
struct RunStats {
  long steps = 0, accepted = 0, rejected = 0, f_evals = 0, jacobians = 0, lu_decompositions = 0;
  double wall_seconds = 0.0;
};

/// Whether the tolerance controls the result (README, "Limits": atol against the motion).
struct Accuracy {
  bool reliable = true;
  double rtol = 0.0, atol = 0.0;
  std::string reason;  ///< why not ("" if reliable)
};

/// Where the run started from with initial.from = "equilibrium" (docs/steady.md).
struct InitialState {
  std::map<std::string, double> q;               ///< the equilibrium coordinates, by name
  double force_imbalance = 0.0;                  ///< the residual of the force balance
  std::map<std::string, double> holding_forces;  ///< the forces holding the slow coordinates
};

/// Why a run ended before solver.t_end.
struct RunEnd {
  double t = 0.0;      ///< s, when
  std::string status;  ///< the engine's status ("" when the model's client stopped the run)
  std::string reason;  ///< in words
};

/// One run of a case. Values are SI (s, m, N, rad) in the model's units.
struct RunResult {
  std::string case_name;      ///< the case's name
  std::string model;          ///< the model's name
  std::string model_variant;  ///< "" (the model itself) or the internal variant run
  std::string kernel, form, method;  ///< the solver keys as run
  std::string methods_used;   ///< "explicit", "radau" or "explicit, then radau from t = ..."
  double t_end = 0.0;         ///< s, solver.t_end
  double window_start = 0.0, window_end = 0.0;  ///< s, the summary window
  bool window_clipped = false;  ///< the window asked for was longer than the run
  int summary_periods = 0;    ///< > 0: the window is this many excitation periods ...
  double period = std::numeric_limits<double>::quiet_NaN();  ///< ... of this length (s)
  double summary_time = 0.0;  ///< else the window's length, s
  RunStats stats;
  std::map<std::string, double> q_end;   ///< the final coordinates, by name
  std::map<std::string, double> qd_end;  ///< the final velocities, by name + "_d"
  /// The time-series columns (timeseries.csv's header): t, coordinates, <name>_d, R_<name>,
  /// outputs, residual_pos, residual_vel, and mode_<contact> with switching.
  std::vector<std::string> columns;
  /// The window extremes of every value column (coordinates, velocities, reactions, outputs).
  std::map<std::string, ColumnExtremes> extremes;
  double constraint_residual_max = 0.0;
  std::vector<std::string> constraints;     ///< the active constraints
  std::map<std::string, double> parameters; ///< every parameter as run
  double output_dt = 0.0;                   ///< s, the time-series interval
  double initial_correction_position = 0.0, initial_correction_velocity = 0.0;
  std::optional<InitialState> initial_state;  ///< with initial.from = "equilibrium"
  Accuracy accuracy;
  bool complete = false;         ///< the run reached t_end
  std::optional<RunEnd> stopped; ///< the model's client ended the run (e.g. off the deck)
  std::optional<RunEnd> failure; ///< the engine failed (status, reason)
  double t_reached = std::numeric_limits<double>::quiet_NaN();  ///< s, with stopped or failure
  /// With contact.switching: summary.json's "switching" object (sim/switching_summary.hpp);
  /// null without.
  nlohmann::json switching;
  /// Issue 21: summary.json's "rank" object (sim/rank_summary.hpp): null when the active rows
  /// have full rank at the start and keep it.
  nlohmann::json rank;
  /// The model client's keys (e.g. the sieve's verdicts and margins), merged into summary.json
  /// over the generic ones; an empty object without a client.
  nlohmann::json additions = nlohmann::json::object();

  /// The extremes of a value column; throws std::out_of_range naming it if there is none.
  const ColumnExtremes& extreme(const std::string& column) const;

  /// A value by its dotted path in summary.json ("extremes.x.max", "stats.steps", "q_end.s",
  /// "window_clipped", a client's "margins.contact"), as to_json(*this) holds it: a number, a
  /// boolean or a string; null if there is none (or it is not finite, or not a scalar).
  nlohmann::json value(const std::string& dotted) const;
};

/// summary.json's content (model-files.md, "summary.json"): the generic keys, then the client's.
nlohmann::json to_json(const RunResult& r);

/// The result a summary.json of a run of `columns` holds (pcsim steady's report reads the
/// summary of its period's run back); to_json of it is `summary` again. Throws
/// nlohmann::json::exception if a generic key is missing or of the wrong type.
RunResult result_from_json(const nlohmann::json& summary, std::vector<std::string> columns);

}  // namespace pcsim::sim
