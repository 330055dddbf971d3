// Running a case of any model: simulate, the window extremes of every column refined on the
// dense output, the time series, the typed result (sim/result.hpp: the generic keys of
// model-files.md plus the model client's additions), the output directory written as a whole
// (summary.json = to_json(result)), and the engineer's report.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/eigen_instances.hpp"

#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/files.hpp"
#include "mech/equilibrium.hpp"
#include "mech/simulation.hpp"
#include "mech/model.hpp"
#include "sim/case.hpp"
#include "sim/result.hpp"

namespace pcsim::sim {

/// The most time-series rows a run writes; a case asking for more (output.dt against
/// solver.t_end) is refused before any computation, naming output.dt and the row count.
inline constexpr double kMaxOutputRows = 1e7;

/// What a run keeps in memory for its caller (RunOptions::keep), the same values the files
/// get: the time-series rows timeseries.csv holds, row-major (timeseries_columns(c) numbers a
/// row; a switching run's mode columns as indices of mech::ContactMode), events.csv's text
/// (with contact.switching), and the result of a run that failed (the summary.json written
/// with "complete": false), which the exception does not carry.
struct Kept {
  std::vector<double> rows;
  std::string events_csv;
  std::optional<RunResult> partial;
};

/// How to run a case: where to write, and the internal options of pcsim's own callers.
struct RunOptions {
  /// Where to write timeseries.csv and summary.json; nullopt writes nothing (sweeps). The
  /// directory is locked for the run and replaced as a whole at its end (common/files.hpp).
  std::optional<std::filesystem::path> out_dir;
  /// Internal (not a case key, not a CLI flag): an equivalent description of the model, passed
  /// to ModelSource::instantiate ("" = the default; the sieve's tests and benchmarks register
  /// its C++ forms "closed_form", "geometric", "analytic": tests/sieve/support/variants.hpp).
  std::string variant;
  /// Internal (not a case key): adjusts the engine's options after the case's, e.g. the path
  /// before issue 14 (the dense compatibility solve, projection after every step) on which the
  /// rolling-as-printed references were made (tests/sieve/support/variants.hpp).
  std::function<void(mech::SimulationOptions&)> engine;
  // Internal (pcsim steady: one period of a periodic orbit through the same run and summary):
  /// wraps the instantiated model (the holding forces of slow coordinates);
  std::function<std::shared_ptr<const mech::Model>(std::shared_ptr<const mech::Model>)> wrap_model;
  /// starts from this state (q, q̇) instead of the case's (the constants of from_initial
  /// constraints still come from the case's initial values);
  std::optional<std::pair<Eigen::VectorXd, Eigen::VectorXd>> start;
  /// writes timeseries.csv into this directory, which the caller owns and commits, instead of
  /// out_dir (summary.json is then the caller's to write).
  OutputDirectory* directory = nullptr;
  /// Internal (the Python module, cpp/python): also keeps in memory what the files hold.
  Kept* keep = nullptr;
  /// Internal (issue 23): the generic monitor (time-series rows, window extremes) observes the
  /// steps on a thread of its own (mech::DeferredObserver), with the same values; false
  /// observes them on the integrating thread (the tests compare the two).
  bool deferred_monitor = true;
};

/// The fewest integration steps that any method can take over `duration` s of a model's
/// motion (README, "Limits"): 2 steps per period of the fastest oscillation of the model
/// linearized at (q0, t = 0) on its active constraints (overdamped modes left out), and 2 per
/// excitation period. Fewer steps than 2 per period cannot resolve an oscillation (its samples
/// alias): the error control of either integrator (the explicit pair and Radau IIA alike)
/// forces at least this many. 0 where it cannot be told (no finite linearization).
struct StepBound {
  double steps = 0;                 ///< the least number of steps over the duration
  double fastest_period = INFINITY; ///< s, the period of the fastest oscillation (inf: none)
};
StepBound minimal_steps(const mech::Model& model, const std::vector<std::string>& active,
                        const Eigen::VectorXd& q0, double excitation_period, double duration);

/// Refuses (pcsim::InputError naming solver.max_steps, the duration's key and the bound) a run
/// of `duration` s whose step budget cannot be enough by minimal_steps(); `what` says what the
/// duration is ("solver.t_end = 10 s", "the orbit period 2*pi/omega = 6e9 s").
void check_step_budget(const Case& c, const Setup& setup, const mech::Model& model, double duration,
                       const std::string& what);

/// The static equilibrium a case starts from with initial.from = "equilibrium": the forces at
/// rest averaged over one excitation period (the model's period; at t = 0 if it has none),
/// balanced by the reactions of the active constraints, the model's slow coordinates held at
/// their initial values (mech/equilibrium.hpp). Throws pcsim::NumericalError (no equilibrium)
/// or pcsim::InputError (a model without exact tangents).
/// The engine's options for running the case as pcsim run does (solver keys, active
/// constraints, projection after accepted steps), from t = 0.
mech::SimulationOptions simulation_options(const Setup& setup);

/// The summary window [w0, w1 = t_end] of a run: its last window.periods excitation periods or
/// window.time seconds, or the whole run (w0 = 0, clipped) when that is longer than the run.
struct SummaryWindow {
  double w0 = 0.0, w1 = 0.0;
  bool clipped = false;
};
SummaryWindow summary_window(const Setup& setup);

mech::EquilibriumResult case_equilibrium(const Case& c, const Setup& setup, const mech::Model& model);

/// A run that completed but whose tolerance does not control its result (summary.json's
/// "accuracy": {"reliable": false}): a NumericalError (exit 3) that carries the result, so the
/// command can still print the report with its UNRELIABLE line before failing.
class UnreliableResult : public NumericalError {
 public:
  UnreliableResult(const std::string& what, double t, RunResult result)
      : NumericalError(what, t), result_(std::move(result)) {}
  const RunResult& result() const { return result_; }

 private:
  RunResult result_;
};

/// Runs the case to solver.t_end and returns its result (summary.json is to_json of it). Thread-safe: concurrent
/// calls on different cases share nothing. Throws pcsim::InputError for what the case asks that
/// cannot be done (too many rows, an output directory in use), pcsim::NumericalError (with the
/// model time and the reason) if the simulation fails, pcsim::sim::UnreliableResult (a
/// NumericalError with the summary) if it completed with an uncontrolled result, pcsim::IoError if output cannot be
/// written.
RunResult run_case(const Case& c, const RunOptions& options = {});

/// The engineer's report printed by `pcsim run` (the client's, or the generic one).
std::string human_report(const Case& c, const RunResult& result);

/// The time-series column names of a case: t, coordinates, <name>_d, R_<name>, outputs,
/// residual_pos, residual_vel, and with contact.switching mode_<name> per switched contact.
std::vector<std::string> timeseries_columns(const Case& c);

/// The unilateral constraints a case switches (contact.switching = true and active), in model
/// order; empty without switching.
std::vector<std::string> switched_contacts(const Case& c);

}  // namespace pcsim::sim
