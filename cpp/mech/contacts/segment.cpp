// The integration adapter of a switching run: one segment between events.
#include "mech/contacts/segment.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "mech/projection.hpp"

namespace pcsim::mech::contacts {

Segment::Segment(const ContactSet& cs, ModeLogic& modes, const SimulationOptions& opt,
                 const SwitchingOptions& sw, SwitchingResult& res, const SwitchingObserver& observer)
    : cs_(cs),
      modes_logic_(modes),
      model_(cs.model()),
      opt_(opt),
      sw_(sw),
      res_(res),
      observer_(observer),
      n_(cs.n()),
      method_(opt.reaction_method),
      rhs_dyn_(cs.model(), opt.kernel),
      sample_dyn_(cs.model(), opt.kernel),
      event_dyn_(cs.model(), opt.kernel) {}

void Segment::begin() {
  fns_ = make_event_functions();
  out_.late = false;
}

void Segment::configure(const Config& cfg, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               bool grazing) {
  cfg_ = cfg;
  layout_ = cs_.layout(cfg);
  gap_offset_.assign(cs_.nc(), 0.0);
  eps_gap_.assign(cs_.nc(), 0.0);
  eps_vel_.assign(cs_.nc(), 0.0);
  for (int c = 0; c < cs_.nc(); ++c) {
    // Rounding-size offsets of this contact's own gap and sliding velocity (ContactSet::gap_round).
    eps_gap_[c] = cs_.gap_round(c, t, q);
    if (cs_[c].friction >= 0)
      eps_vel_[c] = cs_.velocity_round(cs_.row(cs_[c].friction, t, q, qd), qd);
    if (cs_[c].cone()) eps_vel_[c] += cs_.velocity_round(cs_.row(cs_[c].friction2, t, q, qd), qd);
    if (!is_closed(cfg.modes[c]))
      gap_offset_[c] = std::min(cs_.gap(c, t, q), 0.0) - (grazing ? cs_.gap_tol(c, t, q) : 0.0);
  }
  modes_ = cfg.modes;
  eps_force_ = 0.0;
  bool closed = false;
  for (ContactMode m : cfg.modes) closed = closed || is_closed(m);
  if (closed && solve_reactions(event_dyn_, cs_, layout_, cfg_, t, q, qd, ev_solved_, method_) == ModelIssue::none) {
    double f = 0.0;
    for (int c = 0; c < cs_.nc(); ++c)
      f = std::max(f, std::abs(ev_solved_.lambda_n[c]) + ev_solved_.friction(c));
    eps_force_ = 1e-12 * f;
  }
}

bool Segment::rhs(double t, const double* y, double* out) {
  q_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
  qd_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
  if (solve_reactions(rhs_dyn_, cs_, layout_, cfg_, t, q_, qd_, rhs_solved_, method_) != ModelIssue::none) {
    out_.model_failure = rhs_dyn_.message();
    out_.model_failed = true;
    return false;
  }
  Eigen::Map<Eigen::VectorXd>(out, n_) = qd_;
  Eigen::Map<Eigen::VectorXd>(out + n_, n_) = rhs_solved_.qdd;
  return true;
}

std::vector<EventFn> Segment::make_event_functions() const {
  std::vector<EventFn> ev;
  for (int c = 0; c < cs_.nc(); ++c) {
    switch (cfg_.modes[c]) {
      case ContactMode::flight:
        ev.push_back({c, EventFn::gap});
        if (gap_offset_[c] < -2.0 * eps_gap_[c]) ev.push_back({c, EventFn::surfaced});
        break;
      case ContactMode::contact: ev.push_back({c, EventFn::lift_off}); break;
      case ContactMode::stick:
        ev.push_back({c, EventFn::lift_off});
        ev.push_back({c, EventFn::cone_plus});  // a 2-D cone: μ_s λ_n − |λ_t| through 0
        if (!cs_[c].cone()) ev.push_back({c, EventFn::cone_minus});
        break;
      case ContactMode::slip:
        ev.push_back({c, EventFn::lift_off});
        ev.push_back({c, EventFn::sliding});
        break;
    }
  }
  return ev;
}

bool Segment::events(double t, const double* y, double* g) {
  q_e_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
  qd_e_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
  bool solved = false;
  for (std::size_t i = 0; i < fns_.size(); ++i) {
    const EventFn& f = fns_[i];
    if (f.kind == EventFn::surfaced) {
      g[i] = -cs_.gap(f.c, t, q_e_) - eps_gap_[f.c];  // falls through 0 as the gap rises above −rounding
      continue;
    }
    if (f.kind == EventFn::gap) {
      g[i] = cs_.gap(f.c, t, q_e_) - gap_offset_[f.c] + eps_gap_[f.c];
      continue;
    }
    if (f.kind == EventFn::sliding) {
      // A 2-D cone: the sliding velocity along the segment's reference direction through 0
      // (it came to rest, or turned by 90°: the direction is then renewed).
      g[i] = (cs_[f.c].cone() ? cfg_.dir[f.c].dot(cs_.vt2(f.c, t, q_e_, qd_e_))
                              : cfg_.sigma[f.c] * cs_.vt(f.c, t, q_e_, qd_e_)) +
             eps_vel_[f.c];
      continue;
    }
    if (!solved) {
      if (solve_reactions(event_dyn_, cs_, layout_, cfg_, t, q_e_, qd_e_, ev_solved_, method_) != ModelIssue::none)
        return false;
      solved = true;
    }
    const double ln = ev_solved_.lambda_n[f.c], lt = ev_solved_.lambda_t[f.c];
    const double mu = cs_[f.c].mu_s;
    if (f.kind == EventFn::cone_plus && cs_[f.c].cone()) {
      g[i] = eps_force_ + mu * ln - ev_solved_.friction(f.c);
      continue;
    }
    g[i] = eps_force_ + (f.kind == EventFn::lift_off ? ln : f.kind == EventFn::cone_plus ? mu * ln - lt : mu * ln + lt);
  }
  return true;
}

double Segment::shortest_flight(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  double tau = std::numeric_limits<double>::infinity();
  bool solved = false;
  for (int c = 0; c < cs_.nc(); ++c) {
    if (is_closed(cfg_.modes[c]) || !(cs_.gap(c, t, q) <= cs_.gap_tol(c, t, q))) continue;
    const double v = cs_.vn(c, t, q, qd);
    if (!solved) {
      if (solve_reactions(event_dyn_, cs_, layout_, cfg_, t, q, qd, ev_solved_, method_) != ModelIssue::none)
        return tau;
      solved = true;
    }
    const Row r = cs_.normal_row(c, t, q, qd);
    const double a = r.g.dot(ev_solved_.qdd) + r.gamma;
    if (a < 0.0 && v > 0.0) tau = std::min(tau, 2.0 * v / -a);
    else if (a < 0.0) tau = std::min(tau, std::sqrt(2.0 * cs_.gap_tol(c, t, q) / -a));
  }
  return tau;
}

// ---- samples for the observer ----------------------------------------------------------------

void Segment::fill_sample(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Sample& out) {
  out.t = t;
  out.q = q;
  out.qd = qd;
  if (solve_reactions(sample_dyn_, cs_, layout_, cfg_, t, q, qd, sample_solved_, method_) == ModelIssue::none) {
    out.qdd = sample_solved_.qdd;
    out.R = sample_solved_.R;
    out.lambda = sample_solved_.lambda;
    lambda_set_ = sample_solved_.lambda_set;
  } else {
    out.qdd = Eigen::VectorXd::Constant(n_, std::nan(""));
    out.R = out.qdd;
    out.lambda = Eigen::VectorXd::Constant(layout_.s_A, std::nan(""));
    lambda_set_ = Eigen::VectorXd::Constant(layout_.set.size(), std::nan(""));
  }
  // Every row of the set: a sliding contact's friction rows carry the kinetic friction force.
  model_.derived_with_multipliers(t, q, qd, out.qdd, out.R, layout_.set.rows(), lambda_set_, out.derived);
  out.residual_pos = 0.0;
  for (int i : layout_.imposed)
    if (model_.constraints()[i].kind == ConstraintKind::holonomic && modes_logic_.position_level(i))
      out.residual_pos = std::max(out.residual_pos, std::abs(model_.position_residual(i, t, q)));
  out.residual_vel = layout_.s_A > 0
                         ? (sample_dyn_.g.topRows(layout_.s_A) * qd + sample_dyn_.g0.head(layout_.s_A))
                               .cwiseAbs()
                               .maxCoeff()
                         : 0.0;
}

const Sample& Segment::view_at(const void* self, double s) {
  return const_cast<Segment*>(static_cast<const Segment*>(self))->sample_in_step(s);
}

const Sample& Segment::sample_in_step(double s) {
  if (step_ == nullptr || s >= step_end_ || step_end_ == step_->t_prev) s = out_.t;
  if (cache_valid_ && cache_.t == s) return cache_;
  if (s == out_.t) {
    fill_sample(out_.t, out_.q, out_.qd, cache_);
  } else {
    dense_.resize(2 * n_);
    step_->dense(std::max(s, step_->t_prev), dense_.data());
    dq_ = dense_.head(n_);
    dqd_ = dense_.tail(n_);
    fill_sample(s, dq_, dqd_, cache_);
  }
  cache_valid_ = true;
  return cache_;
}

bool Segment::observe(const StepInfo* step, double t_prev, double t, const Eigen::VectorXd& q,
             const Eigen::VectorXd& qd) {
  step_ = step;
  step_end_ = t;
  out_.t = t;
  out_.q = q;
  out_.qd = qd;
  cache_valid_ = false;
  if (!observer_) return true;
  StepView view;
  view.t_prev = t_prev;
  view.t = t;
  view.impl_ = this;
  view.impl_at_ = &Segment::view_at;
  try {
    return observer_(view, modes_);
  } catch (const std::exception& ex) {
    out_.observer_error = std::string("the step observer threw: ") + ex.what();
  } catch (...) {
    out_.observer_error = "the step observer threw an unknown exception";
  }
  return false;
}

// ---- statistics over a step ------------------------------------------------------------------

void Segment::dense_at(const StepInfo& step, double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  dense_.resize(2 * n_);
  step.dense(s, dense_.data());
  q = dense_.head(n_);
  qd = dense_.tail(n_);
}

void Segment::account(const StepInfo& step, double a, double b) {
  if (!(b > a)) return;
  const double w0 = sw_.window_start;
  const double wa = std::max(a, w0), wlen = std::max(0.0, b - wa);
  for (int c = 0; c < cs_.nc(); ++c) {
    ContactStats& st = res_.contacts[c];
    const ContactMode m = cfg_.modes[c];
    if (is_closed(m)) {
      st.run.closed_time += b - a;
      st.window.closed_time += wlen;
    }
    if (m == ContactMode::slip) {
      st.run.slip_time += b - a;
      st.window.slip_time += wlen;
      // ∫ |v_t| and ∫ μ_k λ_n |v_t| by 3-point Gauss-Legendre on the dense output (|v_t| =
      // σ v_t is smooth within a sliding segment).
      auto integrate = [&](double lo, double hi, double& dist, double& energy) {
        if (!(hi > lo)) return;
        const double cm = 0.5 * (lo + hi), hw = 0.5 * (hi - lo), r = std::sqrt(0.6);
        const double xs[3] = {cm - hw * r, cm, cm + hw * r}, ws[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
        for (int k = 0; k < 3; ++k) {
          dense_at(step, xs[k], sq_, sqd_);
          const double v = cs_.speed(c, xs[k], sq_, sqd_);
          double ln = 0.0;
          if (solve_reactions(sample_dyn_, cs_, layout_, cfg_, xs[k], sq_, sqd_, sample_solved_, method_) ==
              ModelIssue::none)
            ln = sample_solved_.lambda_n[c];
          dist += hw * ws[k] * v;
          energy += hw * ws[k] * cs_[c].mu_k * ln * v;
        }
      };
      integrate(a, b, st.run.slip_distance, st.run.energy_friction);
      integrate(wa, b, st.window.slip_distance, st.window.energy_friction);
    }
    if (m == ContactMode::flight) {
      // The flight's highest gap: the step end, and an apex inside the step where the gap
      // rate falls through 0 (bisection on the dense output).
      dense_at(step, b, sq_, sqd_);
      double top = cs_.gap(c, b, sq_);
      dense_at(step, a, sq_, sqd_);
      top = std::max(top, cs_.gap(c, a, sq_));  // a flight that starts high (at t0)
      double va = cs_.vn(c, a, sq_, sqd_);
      dense_at(step, b, sq_, sqd_);
      double vb = cs_.vn(c, b, sq_, sqd_);
      if (va > 0.0 && vb <= 0.0) {
        double lo = a, hi = b;
        for (int it = 0; it < 60 && hi - lo > 1e-14 * (1.0 + std::abs(hi)); ++it) {
          const double mid = 0.5 * (lo + hi);
          dense_at(step, mid, sq_, sqd_);
          if (cs_.vn(c, mid, sq_, sqd_) > 0.0) lo = mid; else hi = mid;
        }
        dense_at(step, 0.5 * (lo + hi), sq_, sqd_);
        top = std::max(top, cs_.gap(c, 0.5 * (lo + hi), sq_));
      }
      if (!st.flights.empty()) st.flights.back().max_gap = std::max(st.flights.back().max_gap, top);
      st.run.max_flight_height = std::max(st.run.max_flight_height, top);
      if (b > w0) st.window.max_flight_height = std::max(st.window.max_flight_height, top);
    }
  }
}

// ---- the step callback -----------------------------------------------------------------------

StepAction Segment::on_step(StepInfo& step) {
  Eigen::Map<Eigen::VectorXd> y(step.y, 2 * n_);
  Eigen::VectorXd q = y.head(n_), qd = y.tail(n_);
  // A gap that dips below zero and comes back within one step is not a sign change of the
  // event function: look for it on the dense output, and end the step there.
  double t_end = step.t;
  bool late = false;
  for (int c = 0; c < cs_.nc() && !late; ++c) {
    if (is_closed(cfg_.modes[c])) continue;
    constexpr int K = 8;
    double prev_t = step.t_prev;  // the last sample with a positive gap
    for (int k = 1; k <= K; ++k) {
      const double s = step.t_prev + (step.t - step.t_prev) * k / K;
      dense_at(step, s, sq_, sqd_);
      // Below the accuracy of the positions (a dip within it is not resolved anyway).
      track_penetration(s, sq_, c);  // this open contact's gap inside the step
      const double g = cs_.gap(c, s, sq_) - gap_offset_[c];
      if (g > 0.0) prev_t = s;
      if (g < -cs_.gap_tol(c, s, sq_)) {
        double lo = prev_t, hi = s;
        for (int it = 0; it < 80 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++it) {
          const double mid = 0.5 * (lo + hi);
          dense_at(step, mid, sq_, sqd_);
          if (cs_.gap(c, mid, sq_) - gap_offset_[c] < 0.0) hi = mid; else lo = mid;
        }
        t_end = hi;
        late = true;
        break;
      }
    }
  }
  // The same for the forces and sliding velocities of closed contacts (a normal force that
  // turns negative and back, or a cone left and re-entered, within one long step: the
  // explicit pair takes steps of a third of the sieve's excitation period while it sticks).
  // They are sampled at a few points inside the step; the first sign change is located by
  // bisection on the dense output.
  bool any_closed_fn = false;
  for (const EventFn& f : fns_) any_closed_fn = any_closed_fn || (f.kind != EventFn::gap && f.kind != EventFn::surfaced);
  if (any_closed_fn) {
    constexpr int K = 4;
    gs_.resize(fns_.size());
    ys_.resize(2 * n_);
    auto negative = [&](double s) {
      step.dense(s, ys_.data());
      if (!events(s, ys_.data(), gs_.data())) return false;
      for (std::size_t i = 0; i < fns_.size(); ++i)
        if (fns_[i].kind != EventFn::gap && fns_[i].kind != EventFn::surfaced && gs_[i] < 0.0) return true;
      return false;
    };
    double prev_t = step.t_prev;
    const double stop = late ? t_end : step.t;
    for (int k = 1; k < K; ++k) {
      const double s = step.t_prev + (stop - step.t_prev) * k / K;
      if (!negative(s)) {
        prev_t = s;
        continue;
      }
      double lo = prev_t, hi = s;
      for (int it = 0; it < 80 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++it) {
        const double mid = 0.5 * (lo + hi);
        (negative(mid) ? hi : lo) = mid;
      }
      t_end = hi;
      late = true;
      break;
    }
  }
  if (late) {
    dense_at(step, t_end, q, qd);
    out_.late_q = q;
    out_.late_qd = qd;
    out_.late_t = t_end;
    out_.late = true;
    ++res_.late_roots;
  }
  bool modified = false;
  if (!late && !layout_.imposed.empty() && !consistent_enough(step.t, q, qd)) {
    double dq = 0.0, dv = 0.0;
    std::string msg;
    const ModelIssue e = modes_logic_.project(layout_, step.t, q, qd, dq, dv, msg);
    if (e != ModelIssue::none) {
      out_.projection_issue = e;
      out_.projection_message = msg;
      return StepAction::stop;
    }
    if (dq > 0.0 || dv > 0.0) {
      y.head(n_) = q;
      y.tail(n_) = qd;
      modified = true;
    }
  }
  track_residuals(t_end, q, qd);
  account(step, step.t_prev, t_end);
  if (!observe(&step, step.t_prev, t_end, q, qd)) {
    out_.stopped = true;
    return StepAction::stop;
  }
  if (late) return StepAction::stop;
  // A 2-D cone's reference direction follows its sliding velocity from step to step, so its
  // event (ref·v through 0) means that the contact stopped, not that its direction turned (a
  // spinning body's contact point turns through every direction while it slides).
  for (int c = 0; c < cs_.nc(); ++c) {
    if (cfg_.modes[c] != ContactMode::slip || !cs_[c].cone()) continue;
    const Eigen::Vector2d v = cs_.vt2(c, step.t, q, qd);
    if (v.dot(cfg_.dir[c]) > 0.0) cfg_.dir[c] = v.normalized();
  }
  return modified ? StepAction::state_modified : StepAction::proceed;
}

// As simulate() decides: a state that satisfies the imposed constraints to the projection's
// tolerance already is left alone (the projection would change it by rounding only, and the
// explicit pair keeps its last evaluation); the pre-issue-14 path projects after every step.
bool Segment::consistent_enough(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  if (opt_.project_every_step) return false;
  // Row by row, each to its own scale (row_within_projection_tol, shared with simulate()).
  for (int i : layout_.imposed) {
    const Row r = cs_.row(i, t, q, qd);
    const bool position =
        model_.constraints()[i].kind == ConstraintKind::holonomic && modes_logic_.position_level(i);
    const double phi = position ? model_.position_residual(i, t, q) : 0.0;
    if (!row_within_projection_tol(r.g, r.g0, position, phi, t, q, qd, opt_.projection_tol))
      return false;
  }
  return true;
}

void Segment::track_penetration(double t, const Eigen::VectorXd& q, int only) {
  for (int c = 0; c < cs_.nc(); ++c) {
    if (only >= 0 && c != only) continue;
    const double pen = -cs_.gap(c, t, q);
    if (!(pen > 0.0)) continue;
    ContactStats& st = res_.contacts[c];
    if (pen > st.run.penetration_max) {
      st.run.penetration_max = pen;
      st.run.penetration_time = t;
    }
    if (t >= sw_.window_start && pen > st.window.penetration_max) {
      st.window.penetration_max = pen;
      st.window.penetration_time = t;
    }
    res_.residual_pos_max = std::max(res_.residual_pos_max, pen);
  }
}

void Segment::track_residuals(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  track_penetration(t, q);
  for (int i : layout_.imposed) {
    const Row r = cs_.row(i, t, q, qd);
    res_.residual_vel_max = std::max(res_.residual_vel_max, std::abs(r.value(qd)));
    if (model_.constraints()[i].kind == ConstraintKind::holonomic && modes_logic_.position_level(i))
      res_.residual_pos_max =
          std::max(res_.residual_pos_max, std::abs(model_.position_residual(i, t, q)));
  }
}

}  // namespace pcsim::mech::contacts
