// run_case for any model: the generic monitor (time-series rows, window extremes of every
// column), the summary, the output directory, and the generic report.
#include "sim/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"
#include <Eigen/SVD>

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "mech/deferred_observer.hpp"
#include "mech/dynamics.hpp"
#include "mech/projection.hpp"
#include "mech/simulation.hpp"
#include "mech/contacts/switching.hpp"
#include "sim/rank_summary.hpp"
#include "sim/switching_summary.hpp"
#include "sim/client.hpp"
#include "sim/extremes.hpp"
#include "sim/row_writer.hpp"

namespace pcsim::sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;
/// The largest model whose oscillation frequencies bound the step budget (minimal_steps).
constexpr int kMaxModalCoordinates = 200;

// The time-series rows, the window extremes of every column, written as the run goes.
class Monitor {
 public:
  Monitor(int n, int n_out, double w0, double w1, double dt, double t_end, RowWriter* csv,
          std::vector<double>* keep = nullptr)
      : n_(n), n_out_(n_out), w0_(w0), w1_(w1), dt_(dt), t_end_(t_end), csv_(csv), keep_(keep),
        rows_(csv || keep), maxima_(3 * n + n_out), minima_(3 * n + n_out), row_(3 * n + n_out + 3) {
    // Rows only when they are written or kept: run_case has then checked that there are at most
    // kMaxOutputRows of them. Without rows t_end / dt is unchecked (it may exceed a long).
    if (rows_) {
      last_row_ = static_cast<long>(std::floor(t_end / dt * (1 + 1e-12)));
      if (last_row_ * dt < t_end * (1 - 1e-12)) ++last_row_;
    }
  }

  int columns() const { return 3 * n_ + n_out_; }

  double value(const mech::Sample& s, int j) const {
    if (j < n_) return s.q[j];
    if (j < 2 * n_) return s.qd[j - n_];
    if (j < 3 * n_) return s.R[j - 2 * n_];
    return s.derived[j - 3 * n_];
  }

  bool observe(const mech::StepView& v) {
    if (v.t == v.t_prev) {  // the consistent initial state
      const mech::Sample s0 = v.at(v.t);
      if (w0_ <= v.t) offer(s0);
      while (rows_ && next_row_ <= last_row_ && row_time(next_row_) <= v.t) {
        add_row(s0);
        ++next_row_;
      }
      return true;
    }
    if (v.t > w0_) window(v);
    while (rows_ && next_row_ <= last_row_ && row_time(next_row_) <= v.t * (1 + 1e-14)) {
      add_row(v.sample(std::min(std::max(row_time(next_row_), v.t_prev), v.t)));
      ++next_row_;
    }
    return true;
  }

  std::map<std::string, ColumnExtremes> extremes(const std::vector<std::string>& names) const {
    std::map<std::string, ColumnExtremes> out;
    for (int j = 0; j < columns(); ++j) {
      ColumnExtremes e;
      e.max = maxima_[j].value;
      e.t_max = maxima_[j].time;
      e.min = -minima_[j].value;
      e.t_min = minima_[j].time;
      out[names[j]] = e;
    }
    return out;
  }

  long rows_written() const { return next_row_; }

 private:
  double row_time(long k) const { return k < last_row_ ? k * dt_ : t_end_; }

  void offer(const mech::Sample& s) {
    for (int j = 0; j < columns(); ++j) {
      const double x = value(s, j);
      maxima_[j].offer(x, s.t);
      minima_[j].offer(-x, s.t);
    }
  }

  // One step inside the window, at a cost that does not grow with the number of columns beyond
  // reading them (issue 23). K+1 samples; each column whose samples promise a new extreme
  // (sim/extremes.hpp) is refined on the dense output by evaluating the dynamics
  // (refine_max_if_promising: each evaluation serves one column) while the run's allowance of
  // such evaluations lasts (kInitialEvaluations, plus kEvaluationsPerStep for each step of the
  // window). Past it, the columns still promising are refined together from M+1 values on a
  // finer grid: the quartic through the values around each column's best (refine_max_on_grid).
  // Models from kInterpolatedGridMinN coordinates have no allowance (each evaluation would
  // serve one column of thousands: a chain of 30 links has 273) and go to the grid at once.
  // M = 32: on the 30-link chain (1 s, rtol 1e-8) the extremes so found differ from a run at
  // rtol 1e-12 by at most 6.9e-7 of their column's range (M = 16: 2e-5).
  //
  // The grid's values cost no evaluation of the dynamics per grid point (grid_values): q and q̇
  // are the dense output's; q̈, R and the multipliers are the polynomial of degree P through P+1
  // full samples of the step (the K+1 and, for P = 8, the midpoints between them); the derived
  // columns are the model's from those. A step past the allowance costs P full samples (the
  // step's start is the previous step's end), whatever the number of columns. Below
  // kInterpolatedGridMinN coordinates (where a full sample costs microseconds) the allowance
  // and the grid of full samples are as before: bricard_a04 (a stored reference) passes the
  // allowance, and its summary stays bit-identical.
  void window(const mech::StepView& v) {
    const double a = std::max(v.t_prev, w0_), b = v.t;
    if (!(b > a)) return;
    constexpr int K = 4, R = M / K;
    // Refinement iterations: a smooth extremum converges in 3-4 parabolic steps and stops on
    // its bracket; a kink (the minimum of |R_s|/R_u where R_s changes sign) converges only
    // linearly, by the bracket halvings of refine_max, and needs up to ~20 for 1e-6 of a step.
    constexpr int kIter = 24;
    // ... and stops earlier once the value has converged to a few units of rounding.
    constexpr double kValueRtol = 1e-14;
    // The exact refinement (allowance left at the step's start) takes its samples as it always
    // has; past it, the step's start is the previous step's end (the state the step began from).
    // Large models have no allowance: each of its evaluations serves one column of thousands.
    const bool cheap = v.has_state() && n_ >= kInterpolatedGridMinN;
    if (cheap)
      allowance_ = 0;
    else
      allowance_ += kEvaluationsPerStep;
    const bool exact = allowance_ > 0 || !cheap;
    s_.resize(M + 1);
    smp_.resize(M + 1);  // assigned in place: the samples' storage is reused
    for (int k = 0; k <= K; ++k) {
      s_[k * R] = at(a, b, k * R);
      if (k == 0 && !exact && have_end_ && end_.t == a)
        smp_[0] = end_;
      else
        smp_[k * R] = v.sample(s_[k * R]);
    }
    end_ = smp_[M];
    have_end_ = true;
    std::vector<double>& sc = sc_;
    sc.resize(K + 1);
    f_.resize(K + 1);
    for (int k = 0; k <= K; ++k) sc[k] = s_[k * R];
    const int cols = columns();
    grid_.clear();  // (column, sign) pairs left to the grid
    auto eval = [&](double x, int j, double sign) {
      --allowance_;
      return sign * value(v.sample(x), j);
    };
    for (int j = 0; j < cols; ++j) {
      for (int side = 0; side < 2; ++side) {
        const double sign = side ? -1.0 : 1.0;
        RunningMax& best = side ? minima_[j] : maxima_[j];
        for (int k = 0; k <= K; ++k) f_[k] = sign * value(smp_[k * R], j);
        if (!max_promising(sc.data(), f_.data(), K, best)) continue;
        if (allowance_ > 0) {
          refine_max(sc, f_, [&](double x) { return eval(x, j, sign); }, best, kIter, kValueRtol);
        } else {
          grid_.push_back(side ? -(j + 1) : j + 1);
        }
      }
    }
    if (grid_.empty()) return;
    if (!cheap) {  // full samples on the grid
      for (int m = 0; m <= M; ++m) {
        if (m % R == 0) continue;
        s_[m] = at(a, b, m);
        smp_[m] = v.sample(s_[m]);
      }
      fg_.resize(M + 1);
      for (int code : grid_) {
        const int j = std::abs(code) - 1;
        const double sign = code < 0 ? -1.0 : 1.0;
        for (int m = 0; m <= M; ++m) fg_[m] = sign * value(smp_[m], j);
        refine_max_on_grid(s_.data(), fg_.data(), M, code < 0 ? minima_[j] : maxima_[j]);
      }
      return;
    }
    grid_values(v, a, b);
    fg_.resize(M + 1);
    for (int code : grid_) {
      const int j = std::abs(code) - 1;
      const double sign = code < 0 ? -1.0 : 1.0;
      for (int m = 0; m <= M; ++m) fg_[m] = sign * grid_value(m, j);
      refine_max_on_grid(s_.data(), fg_.data(), M, code < 0 ? minima_[j] : maxima_[j], true);
    }
  }

  static constexpr int M = 32;
  /// From this many coordinates the grid past the allowance is interpolated (see window()):
  /// the engine's own threshold for its sparse path, under which every stored case runs.
  static constexpr int kInterpolatedGridMinN = mech::Dynamics::kSparseMinN;
  /// The degree of the polynomial in time through the full samples that gives q̈, R and the
  /// multipliers on the grid (P + 1 samples per step, equispaced, M a multiple of P).
  static constexpr int P = 8, kNodeStride = M / P;

  static double at(double a, double b, int m) { return m == M ? b : a + (b - a) * m / M; }

  // Lagrange's weights of the P+1 equispaced nodes at grid point m (row m, P+1 entries).
  static const std::vector<double>& lagrange() {
    static const std::vector<double> w = [] {
      std::vector<double> out(static_cast<std::size_t>((M + 1) * (P + 1)));
      for (int m = 0; m <= M; ++m) {
        const double u = static_cast<double>(m) / kNodeStride;
        for (int k = 0; k <= P; ++k) {
          double l = 1.0;
          for (int i = 0; i <= P; ++i)
            if (i != k) l *= (u - i) / (k - i);
          out[static_cast<std::size_t>(m * (P + 1) + k)] = l;
        }
      }
      return out;
    }();
    return w;
  }

  // The grid's values for the columns in grid_ (see window()): s_, smp_ at the nodes (full
  // samples), the dense output's q and q̇ elsewhere, q̈, R, λ interpolated where a column of R or
  // a derived column needs them.
  void grid_values(const mech::StepView& v, double a, double b) {
    bool need_dynamics = false, need_derived = false;
    for (int code : grid_) {
      const int j = std::abs(code) - 1;
      need_dynamics = need_dynamics || j >= 2 * n_;
      need_derived = need_derived || j >= 3 * n_;
    }
    const std::vector<double>& L = lagrange();
    constexpr int R = M / 4;
    for (int m = 0; m <= M; ++m) {  // the nodes first: the others interpolate them
      if (m % R == 0) continue;
      s_[m] = at(a, b, m);
      if (need_dynamics && m % kNodeStride == 0) smp_[m] = v.sample(s_[m]);
    }
    for (int m = 0; m <= M; ++m) {
      if (m % R == 0 || (need_dynamics && m % kNodeStride == 0)) continue;
      mech::Sample& g = smp_[m];
      g.t = s_[m];
      v.state(s_[m], g.q, g.qd);
      if (!need_dynamics) continue;
      const double* w = &L[static_cast<std::size_t>(m * (P + 1))];
      auto interpolate = [&](Eigen::VectorXd mech::Sample::*field) {
        Eigen::VectorXd& out = g.*field;
        out = w[0] * (smp_[0].*field);
        for (int k = 1; k <= P; ++k) out += w[k] * (smp_[k * kNodeStride].*field);
      };
      // Only what the columns read: R for R columns; q̈, R, λ and the model's derived
      // quantities from them for derived columns.
      interpolate(&mech::Sample::R);
      if (need_derived) {
        interpolate(&mech::Sample::qdd);
        interpolate(&mech::Sample::lambda);
        v.derived(s_[m], g.q, g.qd, g.qdd, g.R, g.lambda, g.derived);
      }
    }
  }
  double grid_value(int m, int j) const { return value(smp_[m], j); }

  // The window's allowance of evaluations for the exact refinement (see window()).
  static constexpr long kInitialEvaluations = 1000, kEvaluationsPerStep = 16;
  long allowance_ = kInitialEvaluations;
  std::vector<int> grid_;
  std::vector<double> sc_, fg_;
  mech::Sample end_;  // the previous window step's end (past the allowance: the next start)
  bool have_end_ = false;

  void add_row(const mech::Sample& s) {
    row_[0] = s.t;
    for (int j = 0; j < columns(); ++j) row_[j + 1] = value(s, j);
    row_[columns() + 1] = s.residual_pos;
    row_[columns() + 2] = s.residual_vel;
    if (modes_) {  // the contacts' modes, as indices of mech::ContactMode (the writer's labels)
      row_.resize(static_cast<std::size_t>(columns() + 3) + modes_->size());
      for (std::size_t k = 0; k < modes_->size(); ++k)
        row_[static_cast<std::size_t>(columns() + 3) + k] = static_cast<double>((*modes_)[k]);
    }
    if (csv_) csv_->add(row_.data());
    if (keep_) keep_->insert(keep_->end(), row_.begin(), row_.end());
  }

 public:
  /// With switching: the contacts' modes during the step being observed (mode columns).
  const std::vector<mech::ContactMode>* modes_ = nullptr;

 private:

  int n_, n_out_;
  double w0_, w1_, dt_, t_end_;
  RowWriter* csv_;
  std::vector<double>* keep_;
  bool rows_;
  long next_row_ = 0, last_row_ = 0;
  std::vector<RunningMax> maxima_, minima_;  // minima hold the negated signal
  std::vector<double> s_, f_;
  std::vector<mech::Sample> smp_;
  std::vector<double> row_;
};

/// initial.from = "equilibrium": the static equilibrium (case_equilibrium) into q0, and what
/// the result says of it.
InitialState equilibrium_start(const Case& c, const mech::Model& model, Eigen::VectorXd& q0) {
  const mech::EquilibriumResult e = case_equilibrium(c, c.setup, model);
  q0 = e.q;
  InitialState start;
  const auto& coords = c.model->coordinates();
  for (std::size_t i = 0; i < coords.size(); ++i) start.q[coords[i]] = e.q[static_cast<int>(i)];
  start.force_imbalance = e.residual;
  const auto slow = c.model->slow_coordinates();
  for (std::size_t k = 0; k < slow.size() && k < static_cast<std::size_t>(e.holding_force.size()); ++k)
    start.holding_forces[slow[k]] = e.holding_force[static_cast<int>(k)];
  return start;
}

/// The generic fields of a run's result: the case and solver as run, the engine's counters,
/// the final state (the start where the engine has none), the parameters and constraints.
void describe_run(RunResult& r, const Case& c, const std::string& variant,
                  const mech::SimulationResult& res, double wall, const Eigen::VectorXd& q0,
                  const Eigen::VectorXd& qd0) {
  const Setup& set = c.setup;
  const auto& coords = c.model->coordinates();
  const int n = static_cast<int>(coords.size());
  r.case_name = c.name;
  r.model = c.model->name();
  r.model_variant = variant;
  r.kernel = to_string(set.kernel);
  r.form = to_string(set.form);
  r.method = to_string(set.method);
  r.methods_used = res.used_explicit && res.used_radau
                       ? "explicit, then radau from t = " + format_significant(res.switch_time, 9)
                       : (res.used_explicit ? "explicit" : "radau");
  r.t_end = set.t_end;
  if (set.window.periods > 0) {
    r.summary_periods = set.window.periods;
    r.period = set.period;
  } else {
    r.summary_time = set.window.time;
  }
  r.stats = {res.stats.steps,     res.stats.accepted,  res.stats.rejected, res.stats.f_evals,
             res.stats.jacobians, res.stats.lu_decompositions, wall};
  const bool have_end = res.q_end.size() == n && res.qd_end.size() == n;
  for (int i = 0; i < n; ++i) {
    r.q_end[coords[i]] = have_end ? res.q_end[i] : q0[i];
    r.qd_end[coords[i] + "_d"] = have_end ? res.qd_end[i] : qd0[i];
  }
  r.constraint_residual_max = std::max(res.residual_pos_max, res.residual_vel_max);
  r.constraints = set.active;
  r.parameters = set.parameters;
  r.output_dt = set.dt;
  r.initial_correction_position = res.initial_correction_pos;
  r.initial_correction_velocity = res.initial_correction_vel;
}

/// "" if atol controls the run's result, else why not (README, "Limits").
std::string atol_problem(const RunResult& r, const ModelSource& source, double atol) {
  // The absolute tolerance against the motion's own magnitudes (README, "Limits"): the error
  // per step of a component y_i is held to atol + rtol |y_i|; where atol is more than a hundredth
  // of a coordinate's or velocity's largest magnitude over the window, not even two digits of
  // that component (and of what depends on it: reactions, verdicts) are controlled. Components
  // a million times smaller than the largest of their kind (rounding-level motion) are left out.
  constexpr double kAtolFraction = 1e-2, kNegligible = 1e-6;
  auto scale = [&](const std::string& col) {
    const ColumnExtremes& e = r.extreme(col);
    const double v = std::max(std::abs(e.min), std::abs(e.max));
    return std::isfinite(v) ? v : 0.0;
  };
  for (int kind = 0; kind < 2; ++kind) {
    double largest = 0;
    for (const auto& q : source.coordinates()) largest = std::max(largest, scale(kind ? q + "_d" : q));
    for (const auto& q : source.coordinates()) {
      const std::string col = kind ? q + "_d" : q;
      const double v = scale(col);
      if (v > 0 && v >= kNegligible * largest && atol > kAtolFraction * v) {
        return "solver.atol = " + format_significant(atol, 3) + " is more than 1/100 of " +
               (kind ? "velocity " : "coordinate ") + col + "'s largest magnitude " +
               format_significant(v, 3) + " over the summary window, so not even its second "
               "digit (nor the reactions and verdicts that depend on it) is controlled; set "
               "solver.atol <= " + format_significant(kAtolFraction * 1e-2 * v, 2);
      }
    }
  }
  return "";
}

}  // namespace

std::vector<std::string> timeseries_columns(const Case& c) {
  const ModelSource& m = *c.model;
  std::vector<std::string> cols = {"t"};
  for (const auto& q : m.coordinates()) cols.push_back(q);
  for (const auto& q : m.coordinates()) cols.push_back(q + "_d");
  for (const auto& q : m.coordinates()) cols.push_back("R_" + q);
  for (const auto& o : m.outputs()) cols.push_back(o);
  cols.push_back("residual_pos");
  cols.push_back("residual_vel");
  for (const auto& u : switched_contacts(c)) cols.push_back("mode_" + u);
  return cols;
}

std::vector<std::string> switched_contacts(const Case& c) {
  std::vector<std::string> out;
  const Setup& s = c.setup;
  if (!s.contact.switching) return out;
  for (const auto& con : c.model->constraints())
    if (con.unilateral && std::find(s.active.begin(), s.active.end(), con.name) != s.active.end())
      out.push_back(con.name);
  return out;
}

SummaryWindow summary_window(const Setup& set) {
  SummaryWindow w;
  w.w1 = set.t_end;
  if (set.window.periods > 0) {
    const double len = set.window.periods * set.period;
    w.clipped = !(len <= set.t_end);
    w.w0 = w.clipped ? 0.0 : set.t_end - len;
  } else {
    w.clipped = !(set.window.time <= set.t_end);
    w.w0 = w.clipped ? 0.0 : set.t_end - set.window.time;
  }
  return w;
}

mech::SimulationOptions simulation_options(const Setup& set) {
  mech::SimulationOptions so;
  so.kernel = set.kernel;
  so.form = set.form;
  so.method = set.method;
  so.linear_algebra = set.linear_algebra;
  so.t0 = 0.0;
  so.t_end = set.t_end;
  so.rtol = set.rtol;
  so.atol = set.atol;
  so.h0 = set.h0;
  so.max_steps = set.max_steps;
  so.active_constraints = set.active;
  so.stabilization = mech::Stabilization::projection;
  return so;
}

RunResult run_case(const Case& c, const RunOptions& options) {
  const Setup& set = c.setup;
  const ModelSource& source = *c.model;
  const int n = static_cast<int>(source.coordinates().size());
  const std::string where = input_location(c.source);

  const double rows = std::floor(set.t_end / set.dt) + 2;
  if ((options.out_dir || options.directory || options.keep) && !(rows <= kMaxOutputRows))
    throw InputError(where + ": key 'output.dt': expected at most " +
                     format_number(kMaxOutputRows) + " time-series rows (solver.t_end / output.dt), "
                     "got " + format_significant(rows, 3) + " rows; raise output.dt");

  // The output directory first: a second run into it is refused before any computation.
  std::unique_ptr<OutputDirectory> out;
  OutputStream csv;
  OutputDirectory* dir = options.directory;
  if (options.out_dir && !dir) {
    out = std::make_unique<OutputDirectory>(*options.out_dir, "run");
    dir = out.get();
  }
  if (dir) {
    csv = dir->open(set.npy ? "timeseries.npy" : "timeseries.csv");
    if (!set.npy) {  // the .npy header is the writer's (it carries the row count)
      csv.buffer() += csv_header_line(timeseries_columns(c));
    }
    // The model the run ran, as a model file (issue 26: pcsim animate draws it from there).
    const std::string model_text = source.definition_text();
    if (!model_text.empty()) {
      std::string origin = source.origin();  // first line: where it came from (for messages)
      std::replace_if(origin.begin(), origin.end(), [](char ch) { return ch == '\n' || ch == '\r'; }, ' ');
      dir->write("model.toml", "# pcsim run: the " + origin + "\n" + model_text);
    }
  }

  std::shared_ptr<const mech::Model> model =
      source.instantiate(set.parameters, set.q0, 0.0, c.table, options.variant);
  Eigen::VectorXd q0 = set.q0, qd0 = set.qd0;
  std::optional<InitialState> start;
  if (options.start) {
    q0 = options.start->first;
    qd0 = options.start->second;
  } else if (set.equilibrium_start) {
    start = equilibrium_start(c, *model, q0);
    qd0.setZero();
  }
  if (options.wrap_model) model = options.wrap_model(model);
  // The step budget against the run's length, before any integration (README, "Limits").
  if (!options.start)
    check_step_budget(c, set, *model, set.t_end,
                      "solver.t_end = " + format_significant(set.t_end, 6) + " s of motion");

  mech::SimulationOptions so = simulation_options(set);
  if (options.engine) options.engine(so);

  const SummaryWindow window = summary_window(set);
  const double w0 = window.w0, w1 = window.w1;
  const bool clipped = window.clipped;

  const int n_out = static_cast<int>(source.outputs().size());
  std::unique_ptr<RowWriter> writer;
  if (dir) {
    const int modes = static_cast<int>(switched_contacts(c).size());  // with contact.switching
    std::vector<std::string> labels;
    for (auto m : {mech::ContactMode::flight, mech::ContactMode::contact, mech::ContactMode::stick,
                   mech::ContactMode::slip})
      labels.push_back(mech::to_string(m));  // index = the enumerator's value
    if (set.npy)
      writer = std::make_unique<RowWriter>(csv, 3 * n + n_out + 3 + modes, modes, labels,
                                           RowWriter::Npy{timeseries_columns(c)});
    else
      writer = std::make_unique<RowWriter>(csv, 3 * n + n_out + 3 + modes, modes, labels);
  }
  if (options.keep) {
    options.keep->rows.clear();
    options.keep->events_csv.clear();
    options.keep->partial.reset();
  }
  Monitor mon(n, n_out, w0, w1, set.dt, set.t_end, writer.get(),
              options.keep ? &options.keep->rows : nullptr);
  std::unique_ptr<ClientMonitor> client_mon = c.client ? c.client->monitor(c, set) : nullptr;

  bool stopped_by_client = false;
  const auto t_start = std::chrono::steady_clock::now();
  mech::SwitchingResult sres;
  if (set.contact.switching) {
    // Issue 12: the contacts switch at their events (mech/contacts/switching.hpp).
    mech::SwitchingOptions sw;
    sw.zeno_time = set.contact.zeno_time;
    sw.flight_hmax = set.contact.flight_hmax;
    sw.window_start = w0;
    sw.max_events = set.contact.max_events;
    sw.lcp_solver = set.contact.lcp_solver == "enumerative" ? lcp::LcpSolver::enumerative
                                                             : lcp::LcpSolver::lemke;
    sres = mech::simulate_switching(
        *model, q0, qd0, so, sw,
        [&](const mech::StepView& v, const std::vector<mech::ContactMode>& modes) {
          if (client_mon && !(client_mon->deferred() ? client_mon->check(v) && client_mon->observe(v)
                                                     : client_mon->observe(v))) {
            stopped_by_client = true;
            return false;
          }
          mon.modes_ = &modes;
          return mon.observe(v);
        });
  } else {
    // The generic monitor only reads (it never stops the run): it observes on a thread of its
    // own, behind the integration (issue 23). The client's monitor may stop the run: it stays
    // here, unless it is split in two (ClientMonitor::deferred); then its observe() goes along
    // and only its check(), which may end the run, stays.
    ClientMonitor* const client_reads =
        client_mon && client_mon->deferred() ? client_mon.get() : nullptr;
    mech::DeferredObserver deferred(
        [&mon, client_reads](const mech::StepView& v) {
          if (client_reads && !client_reads->observe(v)) return false;
          return mon.observe(v);
        },
        options.deferred_monitor);
    static_cast<mech::SimulationResult&>(sres) = mech::simulate(
        *model, q0, qd0, so, [&](const mech::StepView& v) {
          if (client_mon && !(client_reads ? client_mon->check(v) : client_mon->observe(v))) {
            stopped_by_client = true;
            return false;
          }
          return deferred.push(v);
        });
    deferred.finish();
    if (std::string e = deferred.error(); !e.empty() && !stopped_by_client &&
        (sres.status == mech::SimulationStatus::success ||
         sres.status == mech::SimulationStatus::stopped_by_observer)) {
      sres.status = mech::SimulationStatus::observer_error;
      sres.message = std::move(e);
    }
  }
  const mech::SimulationResult& res = sres;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if ((res.status == mech::SimulationStatus::invalid_model &&
       res.issue != mech::ModelIssue::non_finite) ||
      res.status == mech::SimulationStatus::inconsistent_start) {
    throw InputError(where + ": the " + source.origin() + " with the active constraints cannot be "
                     "simulated: " + res.message);
  }
  const bool complete = res.status == mech::SimulationStatus::success;
  const bool client_stop =
      stopped_by_client && res.status == mech::SimulationStatus::stopped_by_observer;
  // A numerical failure (step size too small, step budget used up, a state that is not finite,
  // a failed projection or LCP, a model that cannot be evaluated): what was computed up to the
  // failure is kept (the time-series rows up to the last accepted step, a summary marked
  // "complete": false with the reason and the time), and the run fails with exit 3.
  const std::string failure =
      complete || client_stop
          ? std::string()
          : "the simulation failed at t = " + format_significant(res.t, 9) + " s (" +
                mech::message(res.status) + "): " + res.message;

  RunResult r;
  r.columns = timeseries_columns(c);
  const std::size_t n_modes = switched_contacts(c).size();
  const std::vector<std::string> value_cols(r.columns.begin() + 1, r.columns.end() - 2 - n_modes);
  r.extremes = mon.extremes(value_cols);
  describe_run(r, c, options.variant, res, wall, q0, qd0);
  r.window_start = w0;
  r.window_end = w1;
  r.window_clipped = clipped;
  r.initial_state = std::move(start);
  const std::string unreliable = atol_problem(r, source, set.atol);
  r.accuracy = {unreliable.empty(), set.rtol, set.atol, unreliable};
  r.complete = complete;
  if (set.contact.switching) r.switching = switching_summary(sres, set);
  else r.rank = rank_summary(res, set.active, 0.0);
  // events.csv: the contacts' switches, or the rank changes (issue 21) of a run without them.
  const bool events = set.contact.switching || !rank_event_rows(r.rank).empty();
  const auto events_text = [&] {
    if (set.contact.switching) return events_csv(sres);
    std::string text = "t,kind,constraint,mode_before,mode_after,normal,tangential,vn_before,"
                       "vn_after,vt_before,vt_after,energy_lost\n";
    auto changes = rank_event_rows(r.rank);
    std::stable_sort(changes.begin(), changes.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& row : changes) text += row.second;
    return text;
  };
  if (client_mon) client_mon->finish(res, r);
  if (client_stop) {
    // The model's client ended the run: what was computed up to then is written, marked as
    // such, and the run fails (exit 3) with the client's reason.
    r.stopped = RunEnd{client_mon->stop_time(), "", client_mon->stop_reason()};
    r.t_reached = res.t;
  } else if (!complete) {
    r.failure = RunEnd{res.t, mech::message(res.status), failure};
    r.t_reached = res.t;
  }

  if (out) {
    writer->finish();
    if (events) out->write("events.csv", events_text());
    out->write("summary.json", to_json(r).dump(2) + "\n");
    out->commit();
  } else if (dir) {
    writer->finish();
  }
  if (options.keep) {
    if (events) options.keep->events_csv = events_text();
    if (!complete) options.keep->partial = r;
  }
  if (complete && !unreliable.empty())
    throw UnreliableResult("case '" + c.name + "': the result is not reliable: " + unreliable +
                               (out ? "; wrote it to " + options.out_dir->string() +
                                          " with \"accuracy\": {\"reliable\": false}"
                                    : std::string()),
                           res.t, std::move(r));
  if (!complete) {
    const std::string kept = out ? "; wrote what was computed up to then to " +
                                       options.out_dir->string() + ", marked \"complete\": false"
                                 : std::string();
    if (client_stop)
      throw NumericalError("case '" + c.name + "': " + client_mon->stop_reason() + kept,
                           client_mon->stop_time());
    throw NumericalError("case '" + c.name + "': " + failure + kept, res.t);
  }
  return r;
}

StepBound minimal_steps(const mech::Model& model, const std::vector<std::string>& active,
                        const Eigen::VectorXd& q0, double excitation_period, double duration) {
  StepBound b;
  const int n = model.n();
  if (!(duration > 0) || q0.size() != n) return b;
  const double f_exc = std::isfinite(excitation_period) && excitation_period > 0 ? 1 / excitation_period : 0;
  if (n > kMaxModalCoordinates) {
    b.steps = 2 * duration * f_exc;
    return b;
  }
  const Eigen::VectorXd qd = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd M(n, n);
  Eigen::VectorXd h(n), Q(n), Qp(n), Qm(n);
  model.kinetic_terms(0.0, q0, qd, M, h);
  // K = -dQ/dq and C = -dQ/dq̇ by central differences (relative steps).
  Eigen::MatrixXd K(n, n), C(n, n);
  for (int j = 0; j < n; ++j) {
    const double hq = 1e-6 * (1.0 + std::abs(q0[j]));
    Eigen::VectorXd qp = q0, qm = q0;
    qp[j] += hq;
    qm[j] -= hq;
    model.forces(0.0, qp, qd, Qp);
    model.forces(0.0, qm, qd, Qm);
    K.col(j) = -(Qp - Qm) / (2 * hq);
    Eigen::VectorXd vp = qd, vm = qd;
    vp[j] += 1e-6;
    vm[j] -= 1e-6;
    model.forces(0.0, q0, vp, Qp);
    model.forces(0.0, q0, vm, Qm);
    C.col(j) = -(Qp - Qm) / 2e-6;
  }
  double f_max = 0;
  // The modal estimate costs O(n^3) time and O(n^2) memory: done for models of up to
  // kMaxModalCoordinates coordinates; larger ones are bounded by their excitation only.
  if (n <= kMaxModalCoordinates && M.allFinite() && K.allFinite() && C.allFinite()) {
    // The motion on the active constraints: the null space D of their rows g.
    std::vector<int> rows;
    for (const auto& name : active)
      if (const int i = model.constraint_index(name); i >= 0) rows.push_back(i);
    Eigen::MatrixXd D = Eigen::MatrixXd::Identity(n, n);
    if (!rows.empty()) {
      const int s = static_cast<int>(rows.size());
      Eigen::MatrixXd g(s, n);
      Eigen::VectorXd g0(s), gamma(s);
      model.constraint_rows(rows, 0.0, q0, qd, g, g0, gamma);
      if (g.allFinite()) {
        const Eigen::JacobiSVD<Eigen::MatrixXd> svd(g, Eigen::ComputeFullV);
        const Eigen::VectorXd sv = svd.singularValues();
        int rank = 0;
        for (int i = 0; i < sv.size(); ++i) rank += sv[i] > 1e-10 * std::max(1.0, sv[0]);
        D = svd.matrixV().rightCols(n - rank);
      }
    }
    if (D.cols() > 0) {
      Eigen::MatrixXd Kr = D.transpose() * K * D, Mr = D.transpose() * M * D,
                      Cr = D.transpose() * C * D;
      Kr = 0.5 * (Kr + Kr.transpose()).eval();
      Mr = 0.5 * (Mr + Mr.transpose()).eval();
      Eigen::LLT<Eigen::MatrixXd> llt(Mr);
      if (llt.info() == Eigen::Success) {
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Kr, Mr);
        if (es.info() == Eigen::Success)
          for (int k = 0; k < es.eigenvalues().size(); ++k) {
            const double lambda = es.eigenvalues()[k];
            if (!(lambda > 0)) continue;
            const double w = std::sqrt(lambda);
            const Eigen::VectorXd x = es.eigenvectors().col(k);  // x^T Mr x = 1
            const double zeta = x.dot(Cr * x) / (2 * w);
            if (zeta >= 1) continue;  // overdamped: no oscillation to resolve
            f_max = std::max(f_max, w / (2 * kPi));
          }
      }
    }
  }
  if (f_max > 0) b.fastest_period = 1 / f_max;
  b.steps = 2 * duration * std::max(f_max, f_exc);
  return b;
}

void check_step_budget(const Case& c, const Setup& set, const mech::Model& model, double duration,
                       const std::string& what) {
  const std::string where = input_location(c.source);
  // With switching contacts, every step while a contact flies or slides is at most
  // contact.flight_hmax long: a span of `duration` in flight takes at least duration/flight_hmax
  // steps. Where that is more than the budget, the budget cannot suffice for a run that flies
  // (a bouncing or hopping body flies most of the time): refused before work, naming both keys.
  if (set.contact.switching && set.contact.flight_hmax > 0 && std::isfinite(duration)) {
    const double flight_steps = std::ceil(duration / set.contact.flight_hmax);
    if (flight_steps > static_cast<double>(set.max_steps))
      throw InputError(where + ": keys 'contact.flight_hmax' and 'solver.max_steps': a step of at most "
                       "contact.flight_hmax = " + format_significant(set.contact.flight_hmax, 6) +
                       " s while a contact flies or slides needs up to " +
                       format_significant(flight_steps, 3) + " steps for " + what +
                       ", more than the step budget solver.max_steps = " + std::to_string(set.max_steps) +
                       "; raise contact.flight_hmax (default: a 16th of the excitation period) or "
                       "solver.max_steps, or shorten the time span (README, \"Limits\")");
  }
  const StepBound b = minimal_steps(model, set.active, set.q0, set.period, duration);
  if (!(b.steps > static_cast<double>(set.max_steps))) return;
  std::string why;
  if (std::isfinite(b.fastest_period) &&
      !(std::isfinite(set.period) && set.period < b.fastest_period))
    why = "2 per period of its fastest oscillation, " + format_significant(b.fastest_period, 3) +
          " s, at the initial state";
  else
    why = "2 per excitation period of " + format_significant(set.period, 3) + " s";
  throw InputError(where + ": key 'solver.max_steps': expected a step budget of at least " +
                   format_significant(std::ceil(b.steps), 3) + " steps for " + what + " (" + why +
                   ": no integrator resolves an oscillation with fewer), got " +
                   std::to_string(set.max_steps) + " (at most " + format_number(1e9) +
                   "); shorten the time span or raise solver.max_steps (README, \"Limits\")");
}

mech::EquilibriumResult case_equilibrium(const Case& c, const Setup& set, const mech::Model& model) {
  const std::string where = input_location(c.source);
  if (!model.has_tangents())
    throw InputError(where + ": key 'initial.from': \"equilibrium\" needs a model with exact "
                     "tangents (a model file; the " + c.model->origin() + " instance has none)");
  std::vector<int> active;
  std::string msg;
  if (mech::resolve_constraints(model, set.active, active, msg) != mech::ModelIssue::none)
    throw InputError(where + ": " + msg);
  mech::EquilibriumOptions eo;
  eo.period = set.period;
  for (const auto& name : c.model->slow_coordinates()) {
    const int i = c.model->coordinate_index(name);
    if (i >= 0) eo.held.push_back(i);
  }
  mech::EquilibriumResult e = mech::static_equilibrium(model, active, set.q0, eo);
  if (e.issue != mech::ModelIssue::none)
    throw NumericalError("case '" + c.name + "': initial.from = \"equilibrium\": " + e.message, 0.0);
  return e;
}

namespace {

// The accuracy line of every report: only when the run's tolerance does not control it.
std::string accuracy_line(const RunResult& r) {
  if (r.accuracy.reliable) return "";
  return "  UNRELIABLE: " + r.accuracy.reason + "\n";
}

}  // namespace

std::string human_report(const Case& c, const RunResult& r) {
  if (c.client) {
    std::string rep = c.client->report(c, r);
    if (!rep.empty()) return accuracy_line(r) + rep + accuracy_line(r);
  }
  std::ostringstream os;
  os << "pcsim run: case '" << r.case_name << "' (" << c.model->origin() << ", " << r.kernel
     << " kernel, " << r.form << " form, " << r.methods_used << "), " << format_number(r.t_end)
     << " s of motion\n";
  os << "  constraints:";
  if (r.constraints.empty()) os << " none";
  for (const auto& n : r.constraints) os << ' ' << n;
  os << "\n";
  const double cp = r.initial_correction_position, cv = r.initial_correction_velocity;
  if (cp > 0 || cv > 0)
    os << "  initial state projected onto the constraints: |dq| = " << format_significant(cp, 3)
       << ", |dq_d| = " << format_significant(cv, 3) << "\n";
  char buf[160];
  std::snprintf(buf, sizeof buf, "  summary window: t = %.6g .. %.6g s%s\n", r.window_start,
                r.window_end, r.window_clipped ? " (clipped to the run)" : "");
  os << buf;
  os << "  over the window:         min           max     amplitude\n";
  // The value columns: after t, before the residuals and the modes.
  const std::size_t modes = switched_contacts(c).size();
  for (std::size_t k = 1; k + 2 + modes < r.columns.size(); ++k) {
    const std::string& name = r.columns[k];
    const auto it = r.extremes.find(name);
    if (it == r.extremes.end()) continue;
    const ColumnExtremes& e = it->second;
    auto num = [](double v) { return std::isfinite(v) ? format_significant(v, 6) : std::string("n/a"); };
    std::snprintf(buf, sizeof buf, "    %-14s %13s %13s %13s\n", name.c_str(), num(e.min).c_str(),
                  num(e.max).c_str(), num(e.amplitude()).c_str());
    os << buf;
  }
  os << switching_report(r.switching);
  os << rank_report(r.rank);
  const RunStats& st = r.stats;
  os << "  solver: " << st.steps << " steps (" << st.accepted << " accepted, " << st.rejected
     << " rejected), " << st.f_evals << " f-evaluations; " << format_significant(st.wall_seconds, 3)
     << " s wall; max constraint residual " << format_significant(r.constraint_residual_max, 2)
     << "\n";
  os << accuracy_line(r);
  return os.str();
}

}  // namespace pcsim::sim
