// "Optimization in small" (the paper's design procedure): a derivative-free NLopt optimizer
// (COBYLA) improves a named summary quantity of a case over bounded design keys, subject to
// named inequality constraints, starting from the case's own values.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/case.hpp"
#include "study/sweep.hpp"
#include "sim/vary.hpp"

namespace pcsim::study {

/// `NAME>=VALUE` or `NAME<=VALUE` on a sweep.csv summary column (e.g. rolling_margin>=0.2).
struct Constraint {
  std::string name;
  bool at_least = true;  ///< >= (true) or <= (false)
  double value = 0.0;
  std::string text() const;
};

/// Parses a constraint; throws pcsim::InputError naming it if the form is wrong, NAME is not
/// a numeric summary column (table.hpp summary_columns) or VALUE is not a finite number.
Constraint parse_constraint(const std::string& spec, const sim::Case& base);

/// Throws pcsim::InputError unless `name` is a numeric summary column.
void check_objective_name(const std::string& name, const sim::Case& base);

/// The default objective of a case: its model client's (sim::Client::default_objective; the
/// sieve's is contact_margin); "" (none: --objective is required) for a model without one.
std::string default_objective(const sim::Case& base);

/// The default constraints of `pcsim optimize`: its model client's
/// (sim::Client::default_constraints); none for a model without one.
std::vector<Constraint> default_constraints(const sim::Case& base);

struct OptimizeOptions {
  std::string objective = "contact_margin";  ///< summary column to maximize (or minimize)
  bool maximize = true;
  std::vector<Constraint> constraints;  ///< e.g. default_constraints(base)
  unsigned seed = 1;          ///< nlopt::srand; with a fixed seed the run is reproducible
  int max_evals = 40;         ///< case runs at most
  double xtol_rel = 1e-3;     ///< stop when a step changes the scaled design by less
  double initial_step = 0.1;  ///< first trust-region radius, as a fraction of each range
};

/// One case run of the optimizer.
struct Evaluation {
  int number = 0;                  ///< 1, 2, ...
  std::vector<double> design;      ///< values of the bounded keys, in --vary order
  double objective = 0.0;          ///< NaN if the run failed
  std::vector<double> constraints; ///< the constrained quantities (NaN if missing)
  bool feasible = false;           ///< ran, and every constraint holds
  double violation = 0.0;          ///< sum of constraint violations (0 if feasible)
  std::string error;               ///< why the run failed, if it did
};

struct OptimizeResult {
  std::vector<Evaluation> evaluations;
  std::optional<std::size_t> best;  ///< index into evaluations: best feasible, else least violation
  sim::Case best_case;            ///< base with the best design set (ready for to_toml)
  std::string stop_reason;          ///< NLopt's reason for stopping, in words
};

/// Maximizes (or minimizes) options.objective over the box `bounds` with COBYLA, starting from
/// the case's values clamped into the box. Each design variable is scaled to [0, 1]. A run that
/// fails scores the worst objective seen so far minus 1 (and violates every constraint by 1),
/// which steers COBYLA away without stopping it. `on_evaluation` (optional) is called after
/// every run.
OptimizeResult optimize(const sim::Case& base, const std::vector<sim::Bounds>& bounds,
                        const Runner& runner, const OptimizeOptions& options,
                        const std::function<void(const Evaluation&)>& on_evaluation = {});

}  // namespace pcsim::study
