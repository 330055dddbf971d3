// simulate_switching(): the event loop of a switching run (see switching.hpp and
// docs/switching.md). Integrates a segment with a fixed set of contact modes until an event,
// then lets the mode logic decide the new set, and goes on.
#include "mech/contacts/switching.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/format.hpp"
#include "mech/contacts/contact_set.hpp"
#include "mech/contacts/modes.hpp"
#include "mech/contacts/segment.hpp"
#include "mech/projection.hpp"
#include "ode/integrate.hpp"

namespace pcsim::mech {

using contacts::Accuracy;
using contacts::Config;
using contacts::ContactDef;
using contacts::ContactSet;
using contacts::EventFn;
using contacts::ModeLogic;
using contacts::num;
using contacts::Segment;
using contacts::SegmentOutcome;
using contacts::Solved;

namespace {

void count_event(SwitchingResult& res, const ContactEvent& ev, double w0) {
  ContactStats& st = res.contacts[ev.contact];
  for (ContactStats::Totals* tot : {&st.run, &st.window}) {
    if (tot == &st.window && !(ev.t >= w0)) continue;
    switch (ev.kind) {
      case ContactEventKind::lift_off: ++tot->lift_offs; break;
      case ContactEventKind::impact:
      case ContactEventKind::accumulation:
        ++tot->impacts;
        tot->max_impact_velocity = std::max(tot->max_impact_velocity, -ev.vn_before);
        break;
      case ContactEventKind::slip: ++tot->slips; break;
      case ContactEventKind::stick: ++tot->sticks; break;
      case ContactEventKind::reversal: ++tot->reversals; break;
    }
    tot->energy_impacts += ev.energy_lost;
    if (ev.mode_after == ContactMode::flight && ev.mode_before != ContactMode::flight) ++tot->flights;
    if (ev.mode_after == ContactMode::flight && ev.mode_before == ContactMode::flight) ++tot->flights;  // a rebound
  }
}
/// Why a run is refused before it starts (refused = false: it is not).
struct Refusal {
  bool refused = false;
  SimulationStatus status = SimulationStatus::invalid_model;
  ModelIssue issue = ModelIssue::none;
  std::string message;
};
Refusal refusal(SimulationStatus status, ModelIssue issue, std::string message) {
  return Refusal{true, status, issue, std::move(message)};
}

/// The initial modes of a run at (q, qd) (projected onto the bilateral constraints first, then
/// onto the set the modes impose) into cfg, with the impacts at t0 into res.
Refusal initial_modes(const ContactSet& cs, ModeLogic& logic, const SimulationOptions& options,
                      double w0, Eigen::VectorXd& q, Eigen::VectorXd& qd, Config& cfg,
                      SwitchingResult& res) {
  const Eigen::VectorXd q0 = q, qd0 = qd;
  cfg.modes.assign(cs.nc(), ContactMode::flight);
  cfg.sigma.assign(cs.nc(), 0);
  cfg.dir.assign(cs.nc(), Eigen::Vector2d::Zero());
  // Bilateral constraints first (the contacts are decided on a consistent state).
  std::vector<int> bil;
  for (int i : cs.active())
    if (!cs.model().constraints()[i].contact.unilateral && !cs.model().constraints()[i].contact.is_friction())
      bil.push_back(i);
  ProjectionWork pw;
  std::string msg;
  double dq = 0, dv = 0;
  if (!bil.empty() && project_state(cs.model(), bil, options.t0, q, qd, options.kernel,
                                    options.projection_tol, dq, dv, msg, pw) != ModelIssue::none)
    return refusal(SimulationStatus::inconsistent_start, ModelIssue::inconsistent_constraints,
                   "consistent initial values: " + msg);
  // Contacts declared active start closed when they touch (within the tolerance): project them.
  Config start = cfg;
  std::vector<ContactEvent> none;
  Config decided;
  if (!logic.transition(options.t0, q, qd, start, nullptr, decided, none, true))
    return refusal(SimulationStatus::inconsistent_start, ModelIssue::inconsistent_constraints,
                   "the initial contact modes: " + logic.message());
  for (const ContactEvent& ev : none) {
    res.events.push_back(ev);
    count_event(res, ev, w0);
  }
  cfg = decided;
  res.initial_modes = cfg.modes;
  std::vector<std::string> imposed;
  for (int i : cs.layout(cfg).imposed) imposed.push_back(cs.model().constraints()[i].name);
  const CheckResult ci = check_model(cs.model(), imposed, options.t0, q, qd, options.kernel);
  if (ci.issue != ModelIssue::none)
    return refusal(SimulationStatus::invalid_model, ci.issue, "with the initial contact modes: " + ci.message);
  res.initial_correction_pos = (q - q0).norm();
  res.initial_correction_vel = (qd - qd0).norm();
  return {};
}

/// The run's totals once it ended at (res.t, q).
void finish(const ContactSet& cs, const ModeLogic& logic, double w0, const Eigen::VectorXd& q,
            SwitchingResult& res) {
  res.lcp_solves = logic.lcp_counters().solves;
  res.energy_limited_impacts = logic.impact_counters().energy_limited;
  res.energy_prevented_max = logic.impact_counters().energy_prevented_max;
  for (ContactStats& st : res.contacts)
    if (!st.flights.empty() && st.flights.back().end > res.t) st.flights.back().end = res.t;
  // The time in flight from the flights recorded (their starts and ends are the events), kept
  // apart from closed_time (summed over the steps with the segment's modes): the report's "in
  // flight" is this one, and the two must agree (test_switching_contacts_far_from_origin).
  for (int c = 0; c < cs.nc(); ++c) {
    ContactStats& st = res.contacts[c];
    for (const ContactStats::Flight& f : st.flights) {
      st.run.flight_time += std::max(0.0, f.end - f.start);
      st.window.flight_time += std::max(0.0, f.end - std::max(f.start, w0));
    }
    st.gap_end = cs.gap(c, res.t, q);
    st.gap_tol_end = cs.gap_tol(c, res.t, q);
  }
}

}  // namespace

SwitchingResult simulate_switching(const Model& model, const Eigen::VectorXd& q0,
                                   const Eigen::VectorXd& qd0, const SimulationOptions& options,
                                   const SwitchingOptions& switching,
                                   const SwitchingObserver& observer) {
  SwitchingResult res;
  res.t = options.t0;
  res.q_end = q0;
  res.qd_end = qd0;
  auto refuse = [&](SimulationStatus st, ModelIssue issue, const std::string& msg) {
    res.status = st;
    res.issue = issue;
    res.message = "model '" + model.name() + "': " + msg;
    return res;
  };
  if (options.form != Form::ode)
    return refuse(SimulationStatus::invalid_model, ModelIssue::none,
                  "switching contacts needs the ODE form (solver.form = \"ode\")");
  // The constraint names; then the model and the bilateral constraints as simulate() checks
  // them (the contacts are checked in the set the initial modes impose: all of them together
  // may well exceed the coordinates, as a block's two corners with friction do).
  CheckResult check;
  {
    std::string msg;
    check.issue = resolve_constraints(model, options.active_constraints, check.active, msg);
    if (check.issue != ModelIssue::none)
      return refuse(SimulationStatus::invalid_model, check.issue, msg);
    std::vector<std::string> bilateral;
    for (int i : check.active)
      if (!model.constraints()[i].contact.unilateral && !model.constraints()[i].contact.is_friction())
        bilateral.push_back(model.constraints()[i].name);
    const CheckResult cb = check_model(model, bilateral, options.t0, q0, qd0, options.kernel);
    if (cb.issue != ModelIssue::none) return refuse(SimulationStatus::invalid_model, cb.issue, cb.message);
  }
  std::string why;
  const ContactSet cs(model, check.active, Accuracy{options.atol, options.rtol}, why);
  if (!why.empty()) return refuse(SimulationStatus::invalid_model, ModelIssue::unknown_constraint, why);
  // The two rows of a 2-D cone must measure two directions of sliding: rows that are parallel
  // at the initial state (the same sliding velocity written twice, as a model's variants of one
  // friction row are) would double the friction force.
  for (int c = 0; c < cs.nc(); ++c) {
    if (!cs[c].cone()) continue;
    const contacts::Row a = cs.row(cs[c].friction, options.t0, q0, qd0), b = cs.row(cs[c].friction2, options.t0, q0, qd0);
    const double na = a.g.norm(), nb = b.g.norm();
    if (!(na > 0.0 && nb > 0.0) || std::abs(a.g.dot(b.g)) > (1.0 - 1e-8) * na * nb)
      return refuse(SimulationStatus::invalid_model, ModelIssue::dependent_constraints,
                    "the friction constraints '" + model.constraints()[cs[c].friction].name + "' and '" +
                        model.constraints()[cs[c].friction2].name + "' of the unilateral constraint '" +
                        cs[c].name + "' are parallel at t0: two friction rows at one contact are a 2-D " +
                        "Coulomb cone, the sliding velocity along two orthonormal tangent directions "
                        "(variants of one friction row: activate one)");
  }
  ModeLogic logic(cs, options, switching);
  const int n = model.n();
  for (int c = 0; c < cs.nc(); ++c) {
    const ContactDef& d = cs[c];
    ContactStats st;
    st.name = d.name;
    st.friction = d.friction >= 0 ? model.constraints()[d.friction].name : "";
    res.contacts.push_back(st);
  }
  const double w0 = std::max(options.t0, switching.window_start);
  res.window_length = std::max(0.0, options.t_end - w0);

  // The initial modes: every touching contact as at an event (an approaching one is an impact
  // at t0), the others in flight; then the state projected onto the resulting set.
  Eigen::VectorXd q = q0, qd = qd0;
  Config cfg;
  if (const Refusal r = initial_modes(cs, logic, options, w0, q, qd, cfg, res); r.refused)
    return refuse(r.status, r.issue, r.message);

  Segment run(cs, logic, options, switching, res, observer);
  run.configure(cfg, options.t0, q, qd);
  for (int c = 0; c < cs.nc(); ++c)
    if (!is_closed(cfg.modes[c])) res.contacts[c].flights.push_back({options.t0, options.t_end, cs.gap(c, options.t0, q)});
  run.track_residuals(options.t0, q, qd);
  if (!run.observe(nullptr, options.t0, options.t0, q, qd)) {
    res.status = run.outcome().observer_error.empty() ? SimulationStatus::stopped_by_observer
                                                      : SimulationStatus::observer_error;
    res.message = run.outcome().observer_error;
    res.q_end = q;
    res.qd_end = qd;
    return res;
  }

  double t = options.t0;
  double h_next = options.h0;
  double last_event_time = -std::numeric_limits<double>::infinity();
  int events_at_instant = 0;
  long total_events = static_cast<long>(res.events.size());
  Eigen::VectorXd y(2 * n);
  while (true) {
    ++res.segments;
    run.begin();
    OdeProblem problem;
    problem.n = 2 * n;
    problem.rhs = [&run](double tt, const double* yy, double* f) { return run.rhs(tt, yy, f); };
    Span span;
    span.second_order = n;
    span.second_order_stride = n;
    span.h0 = h_next;
    // A contact that has just left the surface starts its gap function at zero, which the
    // kernels judge by its sign after the first step: that step must end inside the flight, or
    // a flight shorter than one step (the free parabola is integrated exactly, so steps grow
    // fast) would be missed. The first step is kept below a quarter of the predicted flight,
    // 2 v_n / |a_n| with the acceleration of the new set.
    {
      const double tau = run.shortest_flight(t, q, qd);
      if (std::isfinite(tau)) span.h0 = (span.h0 > 0.0 ? std::min(span.h0, 0.25 * tau) : 0.25 * tau);
    }
    span.hmax = options.hmax;
    bool open_or_sliding = false;
    for (ContactMode m : cfg.modes) open_or_sliding = open_or_sliding || m == ContactMode::flight || m == ContactMode::slip;
    if (open_or_sliding && switching.flight_hmax > 0.0)
      span.hmax = span.hmax > 0.0 ? std::min(span.hmax, switching.flight_hmax) : switching.flight_hmax;
    span.max_steps = std::max(1L, options.max_steps - res.stats.steps);
    span.events.count = static_cast<int>(run.event_functions().size());
    span.events.direction.assign(run.event_functions().size(), -1);
    span.events.g = [&run](double tt, const double* yy, double* g) { return run.events(tt, yy, g); };
    y.head(n) = q;
    y.tail(n) = qd;
    const OdeResult rr = integrate_span(problem, t, y, options, span,
                                        [&run](StepInfo& s) { return run.on_step(s); }, res);
    if (rr.h_last > 0.0) h_next = std::abs(rr.h_last);
    const SegmentOutcome& out = run.outcome();
    if (out.projection_issue != ModelIssue::none) {
      res.status = SimulationStatus::projection_failed;
      res.issue = out.projection_issue;
      res.t = rr.t;
      res.message = "drift projection failed at t = " + num(rr.t) + ": " + out.projection_message;
      break;
    }
    if (!out.observer_error.empty()) {
      res.status = SimulationStatus::observer_error;
      res.message = out.observer_error;
      res.t = out.t;
      q = out.q;
      qd = out.qd;
      break;
    }
    if (out.stopped) {
      res.status = SimulationStatus::stopped_by_observer;
      res.t = out.t;
      q = out.q;
      qd = out.qd;
      break;
    }
    const bool late = out.late;
    if (!late && rr.status == OdeStatus::success) {
      res.status = SimulationStatus::success;
      res.t = rr.t;
      q = rr.y.head(n);
      qd = rr.y.tail(n);
      break;
    }
    if (!late && rr.status != OdeStatus::root_found) {
      res.status = out.model_failed ? SimulationStatus::model_failed : SimulationStatus::integration_failed;
      res.t = rr.t;
      res.message = rr.message + (out.model_failed ? "; the model could not be evaluated: " + out.model_failure : "");
      q = rr.y.size() == 2 * n ? Eigen::VectorXd(rr.y.head(n)) : q;
      qd = rr.y.size() == 2 * n ? Eigen::VectorXd(rr.y.tail(n)) : qd;
      break;
    }
    // An event: the state at the root (on its far side), the reactions there with the old set.
    if (late) {
      t = out.late_t;
      q = out.late_q;
      qd = out.late_qd;
    } else {
      t = rr.t;
      q = rr.y.head(n);
      qd = rr.y.tail(n);
    }
    run.track_penetration(t, q);  // the event's state, before any contact is lifted onto its surface
    Solved before;
    logic.reactions(run.layout(), cfg, t, q, qd, before);
    Config next;
    std::vector<ContactEvent> evs;
    if (!logic.transition(t, q, qd, cfg, &before, next, evs, false)) {
      res.status = SimulationStatus::model_failed;
      res.t = t;
      res.message = "switching failed at t = " + num(t) + ": " + logic.message();
      if (logic.lcp_counters().library_unavailable) res.issue = ModelIssue::kernel_failure;
      break;
    }
    for (const ContactEvent& ev : evs) {
      res.events.push_back(ev);
      count_event(res, ev, w0);
      ContactStats& st = res.contacts[ev.contact];
      if (is_closed(ev.mode_before) && !is_closed(ev.mode_after)) st.flights.push_back({t, options.t_end, 0.0});
      if (!is_closed(ev.mode_before) && is_closed(ev.mode_after) && !st.flights.empty()) st.flights.back().end = t;
      if (!is_closed(ev.mode_before) && !is_closed(ev.mode_after) && !st.flights.empty()) {
        st.flights.back().end = t;  // a bounce: one flight ends, the next begins
        st.flights.push_back({t, options.t_end, 0.0});
      }
    }
    total_events += static_cast<long>(evs.size());
    events_at_instant = (t - last_event_time <= 1e-12 * (1.0 + std::abs(t))) ? events_at_instant + 1 : 0;
    last_event_time = t;
    if (events_at_instant > switching.max_events_at_one_instant || total_events > switching.max_events) {
      res.status = SimulationStatus::model_failed;
      res.t = t;
      res.message = "switching does not settle at t = " + num(t) + ": " +
                    (total_events > switching.max_events
                         ? counted(total_events, "event") + ", more than contact.max_events = " +
                               counted(switching.max_events, "event")
                         : counted(events_at_instant, "switch", "switches") + " at one instant");
      break;
    }
    bool surfaced = false;  // a flight came out of the surface: not a grazing landing
    for (std::size_t i = 0; !late && i < rr.roots.size() && i < run.event_functions().size(); ++i)
      surfaced = surfaced || (rr.roots[i] != 0 && run.event_functions()[i].kind == EventFn::surfaced);
    const bool nothing_changed = !surfaced && evs.empty() && next.modes == cfg.modes && next.sigma == cfg.sigma &&
                                 next.dir == cfg.dir;
    cfg = next;
    run.configure(cfg, t, q, qd, nothing_changed);
    if (t >= options.t_end) {
      res.status = SimulationStatus::success;
      res.t = t;
      break;
    }
  }
  res.q_end = q;
  res.qd_end = qd;
  finish(cs, logic, w0, q, res);
  run.track_penetration(res.t, q);
  return res;
}
}  // namespace pcsim::mech
