// `pcsim steady` for a case: the periodic orbit of the case's model (period k T, T the model's
// declared excitation period), its slow coordinates held, found by Newton shooting from the
// case's start (or its static equilibrium), then one period of it run through the same run
// layer as `pcsim run` (the same summary, the model client's verdicts and margins), and the
// results written as steady.json and timeseries.csv (timeseries.npy with output.format = "npy").
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/files.hpp"
#include "ode/integrate.hpp"
#include "sim/case.hpp"
#include "sim/result.hpp"
#include "steady/shooting.hpp"

namespace pcsim::steady {

struct SteadyOptions {
  int periods = 1;  ///< the orbit's period in excitation periods (k)
  /// Where to write steady.json and the time series (nullopt: nowhere). The directory is
  /// written as a whole (common/files.hpp).
  std::optional<std::filesystem::path> out_dir;
  OdeMethod method = OdeMethod::automatic;  ///< the integrator of the shooting
  int max_iterations = 30;
  double newton_tol = 1e-2;
  int max_transient_periods = 256;  ///< ShootingOptions::max_transient_periods
  /// Skip the period summary (the continuation's inner points need only the orbit).
  bool summary = true;
};

/// What a case's orbit problem is at one value of a varied key (continuation) or as given.
class CaseOrbit {
 public:
  /// Throws pcsim::InputError for a case pcsim steady cannot take: no excitation period, a
  /// model without exact tangents (a C++ variant), a key that is not a parameter or a held
  /// value.
  CaseOrbit(const sim::Case& c, int periods, std::string key = "");

  const sim::Case& source_case() const { return case_; }
  const sim::Setup& setup() const { return setup_; }
  const std::string& key() const { return key_; }
  /// The key's value in the case (NaN without a key).
  double base_value() const { return base_value_; }
  /// The problem with the key at `value` (ignored without a key).
  OrbitProblem problem(double value) const;
  OrbitProblem problem() const { return problem(base_value_); }
  /// The derivative of the problem with respect to the key at `value`.
  ParameterDerivative derivative(double value) const;
  /// The start of Newton: the case's state, or its static equilibrium (initial.from), and the
  /// holding forces of that equilibrium (zero otherwise).
  OrbitPoint guess() const;
  /// The slow coordinates held (names), in problem order.
  const std::vector<std::string>& held() const { return held_; }
  /// Slow coordinates the active constraints already fix (not held again).
  const std::vector<std::string>& fixed_slow() const { return fixed_slow_; }
  /// Constraints the case added ([constraints.added]) that hold a slow coordinate rigidly
  /// (indices into the model's constraints): the outputs leave their reaction out.
  const std::vector<int>& holding_constraints() const { return holding_constraints_; }
  const std::vector<int>& active() const { return active_; }

 private:
  sim::ParameterValues parameters_at(double value) const;
  Eigen::VectorXd q0_at(double value) const;
  std::shared_ptr<const mech::Model> model_at(double value) const;

  sim::Case case_;
  sim::Setup setup_;
  int periods_;
  std::string key_;
  enum class KeyKind { none, parameter, held_value } kind_ = KeyKind::none;
  std::string name_;     ///< the parameter's or coordinate's name
  int held_index_ = -1;  ///< the held coordinate's index in problem().slow
  /// Throws pcsim::InputError if the varied key cannot change the periodic orbit (README,
  /// "pcsim response": a flat curve is refused).
  void check_key_moves_the_orbit() const;
  std::string c_slow_names() const;
  double base_value_;
  std::vector<int> active_, slow_;
  std::vector<std::string> held_, fixed_slow_;
  std::vector<int> holding_constraints_;
};

/// The orbit's summary over one period: the case run from the periodic state for k T with the
/// holding forces applied (sim::run_case, the window = the whole period), optionally writing
/// the time series into `dir` (timeseries.csv, or timeseries.npy with output.format = "npy",
/// by pcsim run's writer). Returns the run's result.
sim::RunResult period_summary(const CaseOrbit& orbit, const OrbitResult& result,
                              OutputDirectory* dir = nullptr);

/// The steady.json content of a found orbit (summary: the period summary, or null).
nlohmann::json orbit_json(const CaseOrbit& orbit, const OrbitResult& result,
                          const sim::RunResult* summary);

/// Runs `pcsim steady` on a case: throws pcsim::InputError for what cannot be done and
/// pcsim::NumericalError (exit 3) when Newton does not converge, with the residual reached.
/// Returns steady.json's content.
nlohmann::json steady_case(const sim::Case& c, const SteadyOptions& options);

/// The engineer's report of `pcsim steady`.
std::string steady_report(const sim::Case& c, const nlohmann::json& steady);

/// The shooting options a case implies: its tolerances and step limit, the given method.
ShootingOptions shooting_options(const sim::Setup& setup, OdeMethod method);

}  // namespace pcsim::steady
