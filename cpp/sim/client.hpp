// A model's client: what one model adds to the generic case and run layers (the sieve's extra
// case keys, its working-condition verdicts as additions to the run result, its report and sweep
// columns, which read the typed result).
// Every hook has a neutral default, so a model without a client runs as any model does.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "mech/simulation.hpp"
#include "sim/case.hpp"
#include "sim/result.hpp"

namespace pcsim::sim {

/// Watches one run on behalf of a client (created per run; not shared between threads).
class ClientMonitor {
 public:
  virtual ~ClientMonitor() = default;
  /// Called at t0 (v.t_prev == v.t) and after every accepted step, before the generic monitor.
  /// Returns false to end the run there (e.g. the sieve's roller left the deck); the run then
  /// writes what was computed up to stop_time(), marked incomplete, and fails with stop_reason().
  virtual bool observe(const mech::StepView& v) = 0;
  /// Issue 23: true splits the monitor in two. check() is the part that may end the run; it is
  /// called on the integrating thread, at t0 and after every accepted step. observe() then only
  /// reads (it must not return false); it is called after check() for the same step (unless
  /// check() ended the run), on the generic monitor's thread behind the integration, with the
  /// same samples as in place (mech::DeferredObserver).
  virtual bool deferred() const { return false; }
  /// With deferred(): false ends the run at this step (stop_time(), stop_reason()).
  virtual bool check(const mech::StepView& v) { return true; }
  virtual double stop_time() const { return 0.0; }
  virtual std::string stop_reason() const { return ""; }
  /// Adds the client's keys to result.additions at the end of the run. `result` holds the
  /// generic fields, among them the window extremes of every column (coordinates, velocities,
  /// reactions, outputs) by name.
  virtual void finish(const mech::SimulationResult& engine, RunResult& result) = 0;
};

/// One figure of `pcsim plot` for a run's time series: curves by column name, and an optional
/// horizontal line (a limit such as R_u = 0).
struct PlotFigure {
  std::string file, title, ylabel;
  std::vector<std::pair<std::string, std::string>> curves;  ///< column, legend
  std::string hline_label;
  double hline = 0;
  bool has_hline = false;
  bool hline_in_window = true;  ///< false: the window panel autoscales to the curve alone
  double offset = 0.0, scale = 1.0;  ///< curves plotted as (column - offset) * scale
};

/// A bound on a summary column (`pcsim optimize`'s constraints): column >= value (at_least) or
/// column <= value.
struct SummaryBound {
  std::string column;
  bool at_least = true;
  double value = 0.0;
};

class Client {
 public:
  virtual ~Client() = default;
  /// Case keys the client adds (e.g. the sieve's initial.s0).
  virtual std::vector<KeySpec> extra_keys() const { return {}; }
  /// Checks across keys, after the generic validation; throws pcsim::InputError naming the
  /// file and the key.
  virtual void validate(const std::filesystem::path& file, const toml::table& t) const {}
  /// Adjusts the typed setup to the client's keys (e.g. initial.s0 -> q0 of s).
  virtual void adjust(const toml::table& t, Setup& s) const {}
  /// The client's monitor for one run, or null.
  virtual std::unique_ptr<ClientMonitor> monitor(const Case& c, const Setup& s) const {
    return nullptr;
  }
  /// The engineer's report for `pcsim run`; "" for the generic one.
  virtual std::string report(const Case& c, const RunResult& result) const { return ""; }
  /// The summary columns of sweep.csv; empty for the generic ones.
  virtual std::vector<std::string> sweep_columns() const { return {}; }
  /// Derived sweep columns (e.g. the sieve's margins) for a run: name -> value.
  virtual std::map<std::string, double> derived_columns(const RunResult& result,
                                                        const Case& c) const {
    return {};
  }
  /// The figures `pcsim plot` draws of a run's output directory, from its summary (summary.json,
  /// or a steady.json's "summary") and the columns of its time series; empty for the generic
  /// ones (coordinates, reactions, outputs). Throws pcsim::InputError naming `table` when a
  /// column the figures need is missing.
  virtual std::vector<PlotFigure> figures(const nlohmann::json& summary,
                                          const std::set<std::string>& columns,
                                          const std::string& table) const {
    return {};
  }
  /// The coordinates whose amplitudes `pcsim plot` draws for a frequency response; empty for
  /// every coordinate that moves.
  virtual std::vector<std::string> response_coordinates() const { return {}; }
  /// `pcsim optimize`'s default objective (a summary column; "" for none) and its default
  /// constraints for a case of this model.
  virtual std::string default_objective() const { return ""; }
  virtual std::vector<SummaryBound> default_constraints() const { return {}; }
};

/// Associates a client with a built-in model name (the sieve registers one). Thread-safe.
void register_client(const std::string& model_name, std::shared_ptr<const Client> client);
/// The client of a model name, or null.
std::shared_ptr<const Client> find_client(const std::string& model_name);

}  // namespace pcsim::sim
