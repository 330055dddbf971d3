// simulate(): the ODE and DAE forms on the Radau IIA integrator, with consistent initial values,
// drift control after accepted steps, residual tracking and the step observer.
#include "mech/simulation.hpp"
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

#include "mech/detail/sample_site.hpp"
#include "mech/dynamics.hpp"
#include "mech/projection.hpp"
#include "ode/integrate.hpp"

namespace pcsim::mech {

const Sample& StepView::sample(double s) const { return impl_at_(impl_, s); }

void StepView::state(double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) const {
  if (impl_state_) return impl_state_(impl_, s, q, qd);
  const Sample& x = sample(s);
  q = x.q;
  qd = x.qd;
}

void StepView::derived(double s, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                       const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
                       const Eigen::VectorXd& lambda, Eigen::VectorXd& out) const {
  if (impl_derived_) return impl_derived_(impl_, s, q, qd, qdd, R, lambda, out);
  out = sample(s).derived;
}

OdeOptions ode_options(const SimulationOptions& options) {
  OdeOptions oo;
  oo.kernel = options.kernel;
  oo.rtol = options.rtol;
  oo.atol = options.atol;
  oo.h0 = options.h0;
  oo.hmax = options.hmax;
  oo.max_steps = options.max_steps;
  oo.radau.linear_algebra = options.linear_algebra;
  return oo;
}

OdeResult integrate_span(OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                         const SimulationOptions& options, const Span& span,
                         const StepCallback& on_step, SimulationResult& result) {
  // linear_algebra = lapack is LAPACK's LU on the full Newton system: without the second-order
  // structure (RADAU5's M1), which only the own LU exploits.
  if (options.linear_algebra != RadauOptions::LinearAlgebra::lapack) {
    problem.second_order_count = span.second_order;
    problem.second_order_stride = span.second_order_stride;
  }
  OdeOptions oo = ode_options(options);
  oo.h0 = span.h0;
  oo.hmax = span.hmax;
  oo.max_steps = span.max_steps;
  oo.events = span.events;
  const OdeResult rr = ode_integrate(problem, t0, y0, options.t_end, oo, options.method, on_step);
  result.integrator_status = rr.status;
  result.stats.f_evals += rr.f_evals;
  result.stats.steps += rr.steps;
  result.stats.accepted += rr.accepted;
  result.stats.rejected += rr.rejected;
  result.stats.jacobians += rr.radau_stats.jacobians;
  result.stats.lu_decompositions += rr.radau_stats.lu_decompositions;
  result.stats.linear_solves += rr.radau_stats.linear_solves;
  result.used_explicit = result.used_explicit || rr.used_explicit;
  result.used_radau = result.used_radau || rr.used_radau;
  if (std::isnan(result.switch_time) && !std::isnan(rr.switch_time)) result.switch_time = rr.switch_time;
  return rr;
}

namespace {

class Run {
 public:
  Run(const Model& model, const SimulationOptions& opt, std::vector<int> active)
      : model_(model),
        opt_(opt),
        set_(ActiveSet::of(model, active)),
        active_(set_.rows()),
        dyn_(model, opt.kernel, opt.stabilization, opt.baumgarte_alpha, opt.baumgarte_beta),
        site_(model, opt, active_),
        sample_dyn_(site_.dynamics()),
        n_(model.n()),
        s_(set_.size()),
        method_(opt.reaction_method),
        legacy_(opt.project_every_step),
        q_(n_),
        qd_(n_),
        a_(n_),
        Rv_(n_) {
    // Large models with sparse structure: M and g as sparse values on the per-step paths.
    dyn_.sparse_evaluation = true;  // (the sampling workspace's: SampleSite)
    sparse_rows_ = n_ >= Dynamics::kSparseMinN && model.has_sparse_structure();
    if (sparse_rows_) {
      for (int i : active_)
        holonomic_.push_back(model.constraints()[i].kind == ConstraintKind::holonomic ? 1 : 0);
      phi_.resize(s_);
    }
  }

  int ny() const { return opt_.form == Form::ode ? 2 * n_ : 4 * n_; }

  // Right-hand side of K y' = f(t, y).
  bool rhs(double t, const double* y, double* out) {
    q_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
    qd_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
    ModelIssue e = dyn_.evaluate(set_, t, q_, qd_);
    if (opt_.form == Form::ode) {
      if (e == ModelIssue::none) e = dyn_.solve(method_);
      if (e != ModelIssue::none) return failed(e);
      // Near a singular position the rank watch looks at this step (issue 21).
      if (method_ == ReactionMethod::compatibility_structured || dyn_.rank_revealing)
        step_pivot_ = std::min(step_pivot_, dyn_.rank_revealing ? 0.0 : dyn_.min_pivot_ratio());
      Eigen::Map<Eigen::VectorXd>(out, n_) = qd_;
      Eigen::Map<Eigen::VectorXd>(out + n_, n_) = dyn_.qdd;
      return true;
    }
    if (e == ModelIssue::none) e = dyn_.prepare_compatibility();
    if (e != ModelIssue::none) return failed(e);
    a_ = Eigen::Map<const Eigen::VectorXd>(y + 2 * n_, n_);
    Rv_ = Eigen::Map<const Eigen::VectorXd>(y + 3 * n_, n_);
    Eigen::Map<Eigen::VectorXd>(out, n_) = qd_;
    Eigen::Map<Eigen::VectorXd>(out + n_, n_) = a_;
    dyn_.dae_residuals(a_, Rv_, Eigen::Map<Eigen::VectorXd>(out + 2 * n_, n_),
                       Eigen::Map<Eigen::VectorXd>(out + 3 * n_, n_));
    return true;
  }

  // The full consistent state vector y for (q, q̇) at t: DAE form adds a = q̈ and R.
  ModelIssue fill_state(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                        Eigen::Ref<Eigen::VectorXd> y) {
    y.head(n_) = q;
    y.segment(n_, n_) = qd;
    if (opt_.form == Form::dae) {
      ModelIssue e = sample_dyn_.evaluate(site_.set(), t, q, qd);
      if (e == ModelIssue::none) e = sample_dyn_.solve(ReactionMethod::compatibility);
      if (e != ModelIssue::none) {
        message_ = sample_dyn_.message();
        return e;
      }
      y.segment(2 * n_, n_) = sample_dyn_.qdd;
      y.segment(3 * n_, n_) = sample_dyn_.R;
    }
    return ModelIssue::none;
  }

  // Residuals of the current state; updates the maxima.
  // Residuals of a state (max |Φ| over the active holonomic constraints, max |g q̇ + g0|).
  void residuals(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double& pos,
                 double& vel) {
    pos = vel = 0.0;
    if (s_ == 0) return;
    if (sparse_rows_) {
      pw_.g0.resize(s_);
      pw_.gamma.resize(s_);
      pw_.rows_active.evaluate(model_, active_, t, q, qd, pw_.g0, pw_.gamma);
      model_.position_residuals(active_, t, q, phi_.data());
      for (int k = 0; k < s_; ++k)
        if (holonomic_[static_cast<std::size_t>(k)]) pos = std::max(pos, std::abs(phi_[k]));
      vel = (pw_.rows_active.matrix() * qd + pw_.g0).cwiseAbs().maxCoeff();
      return;
    }
    pw_.g.resize(s_, n_);
    pw_.g0.resize(s_);
    pw_.gamma.resize(s_);
    model_.constraint_rows(active_, t, q, qd, pw_.g, pw_.g0, pw_.gamma);
    for (int i : active_)
      if (model_.constraints()[i].kind == ConstraintKind::holonomic)
        pos = std::max(pos, std::abs(model_.position_residual(i, t, q)));
    vel = (pw_.g * qd + pw_.g0).cwiseAbs().maxCoeff();
  }

  // Residuals of the current state; updates the maxima.
  void track_residuals(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    double pos, vel;
    residuals(t, q, qd, pos, vel);
    res_pos_max_ = std::max(res_pos_max_, pos);
    res_vel_max_ = std::max(res_vel_max_, vel);
  }

  // True if the state satisfies the constraints to the projection's tolerance already: the
  // projection would change it by rounding only, and leaving it alone keeps the integrator's
  // last evaluation valid (an explicit pair reuses it for its next step). A Runge-Kutta method
  // preserves constraints that are linear in q exactly, so for constant rows this is the rule.
  bool consistent_enough(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    if (legacy_) return false;  // the pre-issue-14 path projects after every step
    // Row by row, each to its own scale (row_within_projection_tol, shared with switching).
    if (sparse_rows_) {
      pw_.g0.resize(s_);
      pw_.gamma.resize(s_);
      pw_.rows_active.evaluate(model_, active_, t, q, qd, pw_.g0, pw_.gamma);
      model_.position_residuals(active_, t, q, phi_.data());  // NaN for velocity rows: unread
      return rows_within_projection_tol(pw_.rows_active.matrix(), pw_.g0, holonomic_, phi_, t, q,
                                        qd, opt_.projection_tol);
    }
    pw_.g.resize(s_, n_);
    pw_.g0.resize(s_);
    pw_.gamma.resize(s_);
    model_.constraint_rows(active_, t, q, qd, pw_.g, pw_.g0, pw_.gamma);
    for (int k = 0; k < s_; ++k) {
      const int i = active_[k];
      const bool position = model_.constraints()[i].kind == ConstraintKind::holonomic;
      const double phi = position ? model_.position_residual(i, t, q) : 0.0;
      if (!row_within_projection_tol(pw_.g.row(k), pw_.g0(k), position, phi, t, q, qd,
                                     opt_.projection_tol))
        return false;
    }
    return true;
  }

  // ---- Issue 21: the rank of the active rows along the run (SimulationResult::rank_changes).
  // f(t) = σ_r0/σ_max of the row-scaled g at the state; r0 the rank at the start.
  double rank_ratio(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                    Eigen::VectorXd* sv_out = nullptr) {
    pw_.g.resize(s_, n_);
    pw_.g0.resize(s_);
    pw_.gamma.resize(s_);
    model_.constraint_rows(active_, t, q, qd, pw_.g, pw_.g0, pw_.gamma);
    for (int r = 0; r < s_; ++r) {
      const double nr = pw_.g.row(r).norm();
      if (nr > 0.0) pw_.g.row(r) /= nr;
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(pw_.g);
    const Eigen::VectorXd sv = svd.singularValues();
    if (sv_out) *sv_out = sv;
    if (!sv.allFinite() || sv.size() == 0 || !(sv[0] > 0.0)) return 0.0;
    return r0_ > 0 && r0_ <= sv.size() ? sv[r0_ - 1] / sv[0] : 1.0;
  }
  static int rank_of(const Eigen::VectorXd& sv) {
    int r = 0;
    for (int i = 0; i < sv.size(); ++i) r += sv[i] > kRankReport * sv[0] ? 1 : 0;
    return r;
  }
  // The vanishing limit (Dynamics::set_vanishing_limit): on for the run's workspaces, with the
  // rows dependent from the start as persistent directions and the hand-over threshold at a
  // tenth of the start's smallest pivot ratio where that is below kLimitSwitch.
  void start_limit(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    if (s_ == 0 || opt_.form == Form::dae) return;
    double pivot = 1.0;
    if (sample_dyn_.evaluate(site_.set(), t, q, qd) == ModelIssue::none &&
        sample_dyn_.solve(ReactionMethod::compatibility_structured) == ModelIssue::none &&
        !sample_dyn_.rank_revealing)
      pivot = sample_dyn_.min_pivot_ratio();
    const int persistent = r0_ < s_ ? s_ - r0_ : 0;
    const double sw = std::min(Dynamics::kLimitSwitch, 0.1 * pivot);
    dyn_.set_vanishing_limit(true, persistent, sw);
    site_.set_vanishing_limit(true, persistent, sw);
  }
  void start_rank(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    if (s_ == 0) return;
    // Large sparse models: full rank where the sparse structured solve takes every row (its
    // pivots: no row within about 1e-2 rad of the span of the others, so σ_min of the
    // row-scaled g is far above kRankReport σ_max); the dense SVD (O(s² n): minutes at
    // n = 3000) only where it hands over.
    if (sparse_rows_ && sample_dyn_.evaluate(site_.set(), t, q, qd) == ModelIssue::none &&
        sample_dyn_.solve(ReactionMethod::compatibility_structured) == ModelIssue::none &&
        sample_dyn_.used_sparse && !sample_dyn_.rank_revealing) {
      r0_ = s_;
      // The watch threshold relative to the start: the smallest pivot ratio of a regular chain
      // falls as ~0.66/N (g M⁻¹ gᵀ is a discrete Laplacian along it: 2.2e-2 at N = 30, 6.6e-4
      // at N = 1000), so a fixed threshold watched every step of a long chain with dense SVDs
      // (99 % of a 1000-link run). Approaching a singular position drives the ratio towards 0,
      // far below a tenth of where a run started.
      watch_sparse_ = std::min(kWatchSparse, kWatchSparseRelative * sample_dyn_.min_pivot_ratio());
      return;
    }
    Eigen::VectorXd sv;
    r0_ = 0;
    rank_ratio(t, q, qd, &sv);
    r0_ = rank_of(sv);
    if (r0_ < s_) {
      watching_ = true;
      if (sample_dyn_.evaluate(site_.set(), t, q, qd) == ModelIssue::none)
        dependent_start_ = sample_dyn_.dependent_row_indices(r0_);
    }
  }
  double ratio_at(const StepInfo& step, double s) {
    dense_.resize(ny());
    step.dense(s, dense_.data());
    dq_ = dense_.head(n_);
    dqd_ = dense_.segment(n_, n_);
    return rank_ratio(s, dq_, dqd_);
  }
  // The crossing of f = kRankReport between a and b (f(a) and f(b) on either side).
  double bisect(const StepInfo& step, double a, double b, bool a_low) {
    const double tol = 1e-12 * std::max(1.0, std::abs(b));
    for (int it = 0; it < 80 && b - a > tol; ++it) {
      const double m = 0.5 * (a + b);
      if ((ratio_at(step, m) < kRankReport) == a_low) a = m; else b = m;
    }
    return 0.5 * (a + b);
  }
  // The smallest f in [a, b] (golden section), its place into t.
  double golden(const StepInfo& step, double a, double b, double& t) {
    const double r = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - r * (b - a), d = a + r * (b - a);
    double fc = ratio_at(step, c), fd = ratio_at(step, d);
    const double tol = 1e-12 * std::max(1.0, std::abs(b));
    for (int it = 0; it < 100 && b - a > tol; ++it) {
      if (fc < fd) {
        b = d; d = c; fd = fc; c = b - r * (b - a); fc = ratio_at(step, c);
      } else {
        a = c; c = d; fc = fd; d = a + r * (b - a); fd = ratio_at(step, d);
      }
    }
    t = fc < fd ? c : d;
    return std::min(fc, fd);
  }
  // Fills rank, sigma and rows of `c` at its instant c.t.
  void describe_change(const StepInfo& step, RankChange& c) {
    Eigen::VectorXd sv;
    step.dense(c.t, dense_.data());
    dq_ = dense_.head(n_);
    dqd_ = dense_.segment(n_, n_);
    c.sigma = rank_ratio(c.t, dq_, dqd_, &sv);
    c.rank_before = r0_;
    c.rank = std::min(rank_of(sv), r0_ - 1);
    c.rows.clear();
    if (sample_dyn_.evaluate(site_.set(), c.t, dq_, dqd_) == ModelIssue::none) {
      // The rows a column-pivoted QR leaves outside the rank, less those dependent from the start.
      for (int r : sample_dyn_.dependent_row_indices(c.rank))
        if (std::find(dependent_start_.begin(), dependent_start_.end(), r) == dependent_start_.end())
          c.rows.push_back(r);
    }
  }
  void watch_rank(const StepInfo& step) {
    // Watched: every step of a set dependent from the start; otherwise a step whose evaluations
    // took the rank-revealing path or came within kWatch (sin² of a row's angle to the others'
    // span, about 0.22 rad) of a singular position, and the step after it (a minimum at the
    // boundary between them is located in the later one).
    // Large sparse models watch from a pivot ratio of kWatchSparse, or a tenth of the start's
    // where that is lower (start_rank): a regular pendulum chain
    // has pivots below kWatch in the sparse factor's order, and each watched step costs dense
    // SVDs of g (O(s² n)), minutes at n = 3000. A row within 0.03 rad of the others' span is
    // still watched, and the solve hands over (rank-revealing: watched) at 0.01 rad.
    const bool near = step_pivot_ < (sparse_rows_ ? watch_sparse_ : kWatch) ||
                      method_ != ReactionMethod::compatibility_structured;
    step_pivot_ = 1.0;
    if (s_ == 0 || r0_ == 0 || !(step.t > step.t_prev)) return;
    if (!(watching_ || near || watch_next_)) {
      prev_decreasing_ = false;
      return;
    }
    watch_next_ = near;
    constexpr int K = 4;
    double ts[K + 1], fs[K + 1];
    for (int k = 0; k <= K; ++k) {
      ts[k] = k == K ? step.t : step.t_prev + (step.t - step.t_prev) * k / K;
      fs[k] = ratio_at(step, ts[k]);
    }
    const auto low = [](double f) { return f < kRankReport; };
    if (first_watch_ && low(fs[0])) enter(ts[0]);
    first_watch_ = false;
    // Dips below the threshold between samples that are all above it: local minima of f at a
    // sample (or at the step's start after a decreasing step), refined by golden section.
    for (int k = 0; k < K; ++k) {
      const bool at_start = k == 0 && prev_decreasing_ && fs[0] <= fs[1];
      // A minimum at the step's end is looked for in the last quarter here, and in the first
      // quarter of the next step (at_start there).
      const bool inner = fs[k + 1] <= fs[k] && (k + 1 == K || fs[k + 1] <= fs[k + 2]);
      if (!at_start && !inner) continue;
      const int lo = at_start ? 0 : k, hi = at_start ? 1 : std::min(k + 2, K);
      bool any_low = false;
      for (int j = lo; j <= hi; ++j) any_low = any_low || low(fs[j]);
      if (any_low || fs[at_start ? 0 : k + 1] > 0.1) continue;  // not near a singular position
      RankChange c;
      const double fmin = golden(step, ts[lo], ts[hi], c.t);
      if (!low(fmin)) continue;
      if (!changes_.empty() && !(c.t > changes_.back().t_to)) continue;  // found from both sides
      c.t_from = bisect(step, ts[lo], c.t, false);
      c.t_to = bisect(step, c.t, ts[hi], true);
      describe_change(step, c);
      changes_.push_back(c);
    }
    // Crossings of the threshold at the samples: entering and leaving a low-rank interval.
    for (int k = 0; k < K; ++k) {
      const bool lo0 = low(fs[k]), lo1 = low(fs[k + 1]);
      if (lo1 && fs[k + 1] < best_ && low_) {
        best_ = fs[k + 1];
        open_.t = ts[k + 1];
        describe_change(step, open_);
      }
      if (lo0 == lo1) continue;
      const double tc = bisect(step, ts[k], ts[k + 1], lo0);
      if (lo1) {
        enter(tc);
        best_ = fs[k + 1];
        open_.t = ts[k + 1];
        describe_change(step, open_);
      } else if (low_) {
        open_.t_to = tc;
        if (open_.t_from >= step.t_prev) {  // the whole interval in this step: its smallest f
          double tm;
          if (golden(step, open_.t_from, tc, tm) < best_) {
            open_.t = tm;
            describe_change(step, open_);
          }
        }
        changes_.push_back(open_);
        low_ = false;
      }
    }
    prev_decreasing_ = fs[K] < fs[K - 1];
  }
  void enter(double t) {
    open_ = RankChange{};
    open_.t_from = open_.t = t;
    best_ = INFINITY;
    low_ = true;
  }
  void finish_rank() {
    if (low_) changes_.push_back(open_);
    low_ = false;
  }

  // Called at t0 (step == nullptr) and after every accepted step.
  bool observe(const StepInfo* step, double t, const Eigen::VectorXd& q,
               const Eigen::VectorXd& qd, const StepObserver& observer) {
    site_.look_at(step, t, q, qd);
    if (!observer) return true;
    const StepView view = site_.view();
    try {
      return observer(view);
    } catch (const std::exception& ex) {
      observer_error_ = std::string("the step observer threw: ") + ex.what();
    } catch (...) {
      observer_error_ = "the step observer threw an unknown exception";
    }
    return false;
  }

  StepAction on_step(StepInfo& step, const StepObserver& observer) {
    Eigen::Map<Eigen::VectorXd> y(step.y, ny());
    Eigen::VectorXd q = y.head(n_), qd = y.segment(n_, n_);
    bool modified = false;
    if (opt_.stabilization == Stabilization::projection && s_ > 0 &&
        (opt_.form == Form::dae || !consistent_enough(step.t, q, qd))) {
      double dq = 0.0, dv = 0.0;
      const ModelIssue e = project_state(model_, active_, step.t, q, qd, opt_.kernel,
                                         opt_.projection_tol, dq, dv, message_, pw_);
      if (e != ModelIssue::none) {
        projection_issue_ = e;
        return StepAction::stop;
      }
      if (dq > 0.0 || dv > 0.0 || opt_.form == Form::dae) {
        const ModelIssue e2 = fill_state(step.t, q, qd, y);
        if (e2 != ModelIssue::none) {
          projection_issue_ = e2;
          return StepAction::stop;
        }
        modified = true;
      }
    }
    track_residuals(step.t, q, qd);
    if (opt_.form == Form::ode) watch_rank(step);
    if (!observe(&step, step.t, q, qd, observer)) return StepAction::stop;
    return modified ? StepAction::state_modified : StepAction::proceed;
  }

  bool failed(ModelIssue e) {
    last_issue_ = e;
    last_failure_ = dyn_.message();
    return false;
  }

  const Model& model_;
  SimulationOptions opt_;
  ActiveSet set_;
  std::vector<int> active_;
  Dynamics dyn_;
  detail::SampleSite site_;  // the observers' samples (and its workspace for the rank watch)
  Dynamics& sample_dyn_;
  int n_, s_;
  ReactionMethod method_;
  bool legacy_;
  Eigen::VectorXd q_, qd_, a_, Rv_, dense_, state_;
  ProjectionWork pw_;
  bool sparse_rows_ = false;       // the rows as sparse values (large models with the structure)
  std::vector<char> holonomic_;    // per active row (sparse_rows_ only)
  Eigen::VectorXd phi_;
  Eigen::VectorXd dq_, dqd_;
  double res_pos_max_ = 0.0, res_vel_max_ = 0.0;
  ModelIssue last_issue_ = ModelIssue::none;
  std::string last_failure_;
  ModelIssue projection_issue_ = ModelIssue::none;
  std::string message_;
  std::string observer_error_;
  // Issue 21's rank watch.
  bool watching_ = false, first_watch_ = true, low_ = false, prev_decreasing_ = false;
  double best_ = INFINITY;
  double step_pivot_ = 1.0;  // the smallest min_pivot_ratio() of the step's evaluations
  bool watch_next_ = false;
  static constexpr double kWatch = 0.05;
  static constexpr double kWatchSparse = 1e-3;
  static constexpr double kWatchSparseRelative = 0.1;  // of the start's smallest pivot ratio
  double watch_sparse_ = kWatchSparse;
  int r0_ = 0;
  std::vector<int> dependent_start_;
  RankChange open_;
  std::vector<RankChange> changes_;
};

}  // namespace

SimulationResult simulate(const Model& model, const Eigen::VectorXd& q0,
                          const Eigen::VectorXd& qd0, const SimulationOptions& options,
                          const StepObserver& observer) {
  SimulationResult result;
  result.t = options.t0;
  // The state reached: the start until the integration moves it (a run failing before its
  // first step still reports where it stood).
  result.q_end = q0;
  result.qd_end = qd0;
  const CheckResult check =
      check_model(model, options.active_constraints, options.t0, q0, qd0, options.kernel);
  if (check.issue != ModelIssue::none) {
    result.status = SimulationStatus::invalid_model;
    result.issue = check.issue;
    result.message = "model '" + model.name() + "': " + check.message;
    return result;
  }
  const int n = model.n();
  Eigen::VectorXd q = q0, qd = qd0;
  {
    ProjectionWork pw;
    std::string msg;
    const ModelIssue e = project_state(model, check.active, options.t0, q, qd, options.kernel,
                                       options.projection_tol, result.initial_correction_pos,
                                       result.initial_correction_vel, msg, pw);
    if (e != ModelIssue::none) {
      result.status = SimulationStatus::inconsistent_start;
      result.issue = e;
      result.message = "model '" + model.name() + "': consistent initial values: " + msg;
      return result;
    }
  }
  Run run(model, options, check.active);
  Eigen::VectorXd y0(run.ny());
  if (const ModelIssue e = run.fill_state(options.t0, q, qd, y0); e != ModelIssue::none) {
    result.status = SimulationStatus::invalid_model;
    result.issue = e;
    result.message = "model '" + model.name() + "': at the initial state: " + run.message_;
    return result;
  }
  run.track_residuals(options.t0, q, qd);
  run.start_rank(options.t0, q, qd);
  run.start_limit(options.t0, q, qd);
  result.rank_start = run.s_ > 0 ? run.r0_ : 0;
  result.dependent_start = run.dependent_start_;
  if (!run.observe(nullptr, options.t0, q, qd, observer)) {
    result.status = run.observer_error_.empty() ? SimulationStatus::stopped_by_observer
                                                : SimulationStatus::observer_error;
    result.message = run.observer_error_;
    result.q_end = q;
    result.qd_end = qd;
    result.residual_pos_max = run.res_pos_max_;
    result.residual_vel_max = run.res_vel_max_;
    return result;
  }

  OdeProblem problem;
  problem.n = run.ny();
  problem.rhs = [&run](double t, const double* y, double* f) { return run.rhs(t, y, f); };
  if (options.form == Form::dae) {
    problem.mass = Eigen::MatrixXd::Zero(4 * n, 4 * n);
    problem.mass.topLeftCorner(2 * n, 2 * n).setIdentity();
  }
  // Second-order structure (RADAU5's M1, M2): q' = v in both forms and v' = a in the DAE form,
  // so Radau's linear systems shrink to the remaining rows (n instead of 2n in the ODE form).
  Span span;
  span.h0 = options.h0;
  span.hmax = options.hmax;
  span.max_steps = options.max_steps;
  span.second_order = options.form == Form::ode ? n : 2 * n;
  span.second_order_stride = n;
  const OdeResult rr = integrate_span(
      problem, options.t0, y0, options, span,
      [&run, &observer](StepInfo& step) { return run.on_step(step, observer); }, result);

  result.status = rr.status == OdeStatus::success               ? SimulationStatus::success
                  : rr.status == OdeStatus::stopped_by_callback ? SimulationStatus::stopped_by_observer
                                                                : SimulationStatus::integration_failed;
  result.t = rr.t;
  result.message = rr.message;
  result.q_end = rr.y.size() == run.ny() ? Eigen::VectorXd(rr.y.head(n)) : q;
  result.qd_end = rr.y.size() == run.ny() ? Eigen::VectorXd(rr.y.segment(n, n)) : qd;
  result.residual_pos_max = run.res_pos_max_;
  result.residual_vel_max = run.res_vel_max_;
  run.finish_rank();
  result.rank_changes = run.changes_;
  if (run.projection_issue_ != ModelIssue::none) {
    result.status = SimulationStatus::projection_failed;
    result.issue = run.projection_issue_;
    result.message = "drift projection failed at t = " + std::to_string(rr.t) + ": " + run.message_;
  } else if (!run.observer_error_.empty()) {
    result.status = SimulationStatus::observer_error;
    result.message = run.observer_error_;
  } else if (rr.status != OdeStatus::success && rr.status != OdeStatus::stopped_by_callback &&
             run.last_issue_ != ModelIssue::none) {
    result.status = SimulationStatus::model_failed;
    result.issue = run.last_issue_;
    result.message += (result.message.empty() ? "" : "; ") +
                      std::string("the model could not be evaluated: ") + run.last_failure_;
  }
  return result;
}

}  // namespace pcsim::mech
