// Optimization in small with NLopt's COBYLA.
#include "study/optimize.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>

#include <nlopt.hpp>

#include "common/error.hpp"
#include "sim/client.hpp"
#include "study/table.hpp"

namespace pcsim::study {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_numeric_column(const sim::Case& base, const std::string& name) {
  const auto c = summary_columns(base);
  return std::find(c.begin(), c.end(), name) != c.end();
}

/// Columns that are not a number on every run: verdicts (true/false), the window flag, and the
/// first violation times (empty while a condition holds). The optimizer cannot use them.
std::string not_optimizable(const std::string& name) {
  if (name.rfind("first_violation.", 0) == 0)
    return "it is a time that exists only once the condition fails (empty while it holds); "
           "optimize the margin instead (contact_margin, rolling_margin)";
  if (name.size() > 5 && name.compare(name.size() - 5, 5, "_kept") == 0)
    return "it is a verdict (true or false), not a quantity; optimize the margin instead";
  if (name == "window_clipped") return "it is a flag (true or false), not a quantity";
  return "";
}

std::string stop_text(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "objective reached the stop value";
    case nlopt::FTOL_REACHED: return "objective changes below tolerance";
    case nlopt::XTOL_REACHED: return "design steps below tolerance (converged)";
    case nlopt::MAXEVAL_REACHED: return "evaluation limit reached";
    case nlopt::MAXTIME_REACHED: return "time limit reached";
    default: return "stopped (NLopt result " + std::to_string(static_cast<int>(r)) + ")";
  }
}

/// The state COBYLA's callbacks share: runs each design once (the objective and every
/// constraint at the same x reuse one run).
struct Problem {
  const sim::Case& base;
  const std::vector<sim::Bounds>& bounds;
  const Runner& runner;
  const OptimizeOptions& options;
  const std::function<void(const Evaluation&)>& on_evaluation;
  std::vector<Evaluation> evaluations;
  std::map<std::vector<double>, std::size_t> seen;  // scaled design -> evaluation
  double worst = kNaN;                              // worst objective so far (sense-adjusted)

  std::vector<double> design_of(const std::vector<double>& t) const {
    std::vector<double> x(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double ti = std::clamp(t[i], 0.0, 1.0);
      x[i] = bounds[i].low + ti * (bounds[i].high - bounds[i].low);
    }
    return x;
  }

  sim::Case case_of(const std::vector<double>& x) const {
    sim::Case c = base;
    for (std::size_t i = 0; i < x.size(); ++i)
      sim::set_value(c, {bounds[i].key, format_number(x[i])});
    return c;
  }

  const Evaluation& evaluate(const std::vector<double>& t) {
    if (auto it = seen.find(t); it != seen.end()) return evaluations[it->second];
    Evaluation e;
    e.number = static_cast<int>(evaluations.size()) + 1;
    e.design = design_of(t);
    e.objective = kNaN;
    e.constraints.assign(options.constraints.size(), kNaN);
    try {
      const sim::Case c = case_of(e.design);
      const auto columns = summary_columns(c);
      const auto fields = numeric_fields(columns, flatten_summary(runner(c), c, columns));
      if (auto o = fields.find(options.objective); o != fields.end()) e.objective = o->second;
      for (std::size_t k = 0; k < options.constraints.size(); ++k)
        if (auto v = fields.find(options.constraints[k].name); v != fields.end())
          e.constraints[k] = v->second;
      if (std::isnan(e.objective)) e.error = "the summary has no " + options.objective;
    } catch (const std::exception& ex) {
      e.error = ex.what();
    }
    e.feasible = e.error.empty();
    for (std::size_t k = 0; k < options.constraints.size(); ++k) {
      const auto& con = options.constraints[k];
      const double v = e.constraints[k];
      const double gap = std::isnan(v) ? 1.0 : (con.at_least ? con.value - v : v - con.value);
      if (gap > 0) {
        e.feasible = false;
        e.violation += gap;
      }
    }
    if (e.error.empty()) {
      const double s = options.maximize ? e.objective : -e.objective;
      worst = std::isnan(worst) ? s : std::min(worst, s);
    }
    seen.emplace(t, evaluations.size());
    evaluations.push_back(e);
    if (on_evaluation) on_evaluation(evaluations.back());
    return evaluations.back();
  }

  /// COBYLA minimizes: the sense-adjusted objective, negated.
  double cost(const std::vector<double>& t) {
    const Evaluation& e = evaluate(t);
    if (!e.error.empty()) return -((std::isnan(worst) ? 0.0 : worst) - 1.0);
    return options.maximize ? -e.objective : e.objective;
  }

  /// Constraint k in NLopt's form c(t) <= 0.
  double constraint(std::size_t k, const std::vector<double>& t) {
    const Evaluation& e = evaluate(t);
    const auto& con = options.constraints[k];
    const double v = e.constraints[k];
    if (!e.error.empty() || std::isnan(v)) return 1.0;
    // Scaled by the bound's magnitude so that every constraint is O(1) for COBYLA.
    const double scale = std::max(std::abs(con.value), 1e-12);
    return (con.at_least ? con.value - v : v - con.value) / scale;
  }
};

}  // namespace

std::string Constraint::text() const {
  return name + (at_least ? ">=" : "<=") + format_number(value);
}

Constraint parse_constraint(const std::string& spec, const sim::Case& base) {
  std::size_t pos = spec.find(">=");
  bool at_least = true;
  if (pos == std::string::npos) {
    pos = spec.find("<=");
    at_least = false;
  }
  if (pos == std::string::npos)
    throw InputError("--constraint '" + spec + "': expected NAME>=VALUE or NAME<=VALUE");
  std::string name = spec.substr(0, pos);
  while (!name.empty() && name.back() == ' ') name.pop_back();
  while (!name.empty() && name.front() == ' ') name.erase(0, 1);
  if (const std::string why = not_optimizable(name); !why.empty())
    throw InputError("--constraint '" + spec + "': '" + name + "' cannot be constrained: " + why);
  if (!is_numeric_column(base, name))
    throw InputError("--constraint '" + spec + "': unknown quantity '" + name +
                     "' (use a sweep.csv summary column of this case, e.g. " +
                     summary_columns(base).front() + ")");
  std::string value = spec.substr(pos + 2);
  while (!value.empty() && value.front() == ' ') value.erase(0, 1);
  while (!value.empty() && value.back() == ' ') value.pop_back();
  double v = 0.0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (value.empty() || ec != std::errc() || end != value.data() + value.size() ||
      !std::isfinite(v))
    throw InputError("--constraint '" + spec + "': value '" + value + "' is not a number");
  return Constraint{name, at_least, v};
}

void check_objective_name(const std::string& name, const sim::Case& base) {
  if (const std::string why = not_optimizable(name); !why.empty())
    throw InputError("--objective '" + name + "': cannot be optimized: " + why);
  if (!is_numeric_column(base, name))
    throw InputError("--objective '" + name +
                     "': not a summary quantity of this case (use a sweep.csv summary column, "
                     "e.g. " + summary_columns(base).front() + ")");
}

std::string default_objective(const sim::Case& base) {
  return base.client ? base.client->default_objective() : "";
}

std::vector<Constraint> default_constraints(const sim::Case& base) {
  std::vector<Constraint> out;
  if (base.client)
    for (const auto& b : base.client->default_constraints())
      out.push_back({b.column, b.at_least, b.value});
  return out;
}

OptimizeResult optimize(const sim::Case& base, const std::vector<sim::Bounds>& bounds,
                        const Runner& runner, const OptimizeOptions& options,
                        const std::function<void(const Evaluation&)>& on_evaluation) {
  Problem p{base, bounds, runner, options, on_evaluation, {}, {}, kNaN};
  const unsigned n = static_cast<unsigned>(bounds.size());
  nlopt::srand(options.seed);
  nlopt::opt opt(nlopt::LN_COBYLA, n);
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(options.max_evals);
  opt.set_xtol_rel(options.xtol_rel);
  opt.set_initial_step(std::vector<double>(n, options.initial_step));
  opt.set_min_objective(
      [](unsigned, const double* t, double*, void* data) {
        auto* pp = static_cast<Problem*>(data);
        return pp->cost(std::vector<double>(t, t + pp->bounds.size()));
      },
      &p);
  struct ConstraintData {
    Problem* p;
    std::size_t k;
  };
  std::vector<ConstraintData> cdata;
  cdata.reserve(options.constraints.size());
  for (std::size_t k = 0; k < options.constraints.size(); ++k) {
    cdata.push_back({&p, k});
    opt.add_inequality_constraint(
        [](unsigned, const double* t, double*, void* data) {
          auto* cd = static_cast<ConstraintData*>(data);
          return cd->p->constraint(cd->k, std::vector<double>(t, t + cd->p->bounds.size()));
        },
        &cdata.back(), 0.0);
  }

  // The starting design: the case's own values, clamped into the box.
  std::vector<double> t(n);
  for (unsigned i = 0; i < n; ++i) {
    const double v = base.table.at_path(bounds[i].key).value_or(bounds[i].low);
    t[i] = std::clamp((v - bounds[i].low) / (bounds[i].high - bounds[i].low), 0.0, 1.0);
  }
  OptimizeResult result;
  double cost = 0.0;
  try {
    result.stop_reason = stop_text(opt.optimize(t, cost));
  } catch (const nlopt::roundoff_limited&) {
    result.stop_reason = "round-off limited";
  } catch (const std::exception& e) {
    result.stop_reason = std::string("NLopt stopped: ") + e.what();
  }

  result.evaluations = std::move(p.evaluations);
  for (std::size_t i = 0; i < result.evaluations.size(); ++i) {
    const Evaluation& e = result.evaluations[i];
    if (!e.error.empty()) continue;
    if (!result.best) {
      result.best = i;
      continue;
    }
    const Evaluation& b = result.evaluations[*result.best];
    const double se = options.maximize ? e.objective : -e.objective;
    const double sb = options.maximize ? b.objective : -b.objective;
    const bool better = e.feasible != b.feasible ? e.feasible
                        : e.feasible             ? se > sb
                                                 : e.violation < b.violation;
    if (better) result.best = i;
  }
  result.best_case = base;
  if (result.best) {
    const auto& x = result.evaluations[*result.best].design;
    for (std::size_t i = 0; i < x.size(); ++i)
      sim::set_value(result.best_case, {bounds[i].key, format_number(x[i])});
  }
  return result;
}

}  // namespace pcsim::study
