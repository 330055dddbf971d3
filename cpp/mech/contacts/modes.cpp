// The mode logic: impacts, mode decisions, consistency, projection, events of an instant.
#include "mech/contacts/modes.hpp"

#include <algorithm>
#include <cmath>

#include "linalg/huang.hpp"

namespace pcsim::mech::contacts {

ModeLogic::ModeLogic(const ContactSet& cs, const SimulationOptions& opt, const SwitchingOptions& sw)
    : cs_(cs),
      kernel_(opt.kernel),
      projection_tol_(opt.projection_tol),
      method_(opt.reaction_method),
      lcp_policy_(sw.lcp),
      lcp_solver_(sw.lcp_solver),
      aux_dyn_(cs.model(), opt.kernel),
      impact_(cs, aux_dyn_, sw.zeno_time,
              LcpSettings{sw.lcp == SwitchingOptions::Lcp::several_contacts, sw.lcp_solver},
              lcp_counters_),
      anchored_(cs.nc(), 1) {
  shares_.pending_loss.assign(cs.nc(), 0.0);
}

ModelIssue ModeLogic::reactions(const Layout& L, const Config& cfg, double t,
                                const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Solved& out) {
  return solve_reactions(aux_dyn_, cs_, L, cfg, t, q, qd, out, method_);
}

/// Decides the modes of the touching contacts at (t, q, qd) (after any impact): the
/// acceleration-level complementarity problem of normal forces and, for contacts at rest
/// tangentially, the Coulomb cone with μ_s; sliding contacts keep their direction with μ_k.
bool ModeLogic::decide(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg,
                       bool force_lcp) {
  cfg.modes.assign(cs_.nc(), ContactMode::flight);
  cfg.sigma.assign(cs_.nc(), 0);
  cfg.dir.assign(cs_.nc(), Eigen::Vector2d::Zero());
  Problem p;
  for (int c = 0; c < cs_.nc(); ++c) {
    if (!(cs_.gap(c, t, q) <= cs_.gap_tol(c, t, q)) || !(cs_.vn(c, t, q, qd) <= cs_.vn_tol(c, t, q, qd))) continue;
    Cand k;
    k.c = c;
    if (cs_[c].friction >= 0) {
      const Eigen::Vector2d v = cs_.vt2(c, t, q, qd);
      if (v.norm() <= cs_.vt_tol(c, t, q, qd)) {
        k.frictional = true;
        k.mu = cs_[c].mu_s;
      } else {
        k.sigma = v[0] > 0 || cs_[c].cone() ? 1 : -1;
        if (cs_[c].cone()) k.dir = v / v.norm();  // a 2-D cone slides along v
        k.mu = cs_[c].mu_k;
      }
    }
    p.cands.push_back(k);
  }
  if (p.cands.empty()) return true;
  // Rough rows (ContactInfo::rough) hold while their contact is closed: they are imposed with
  // the bilateral rows for every candidate. A candidate that separates with them is open, so
  // its rows are released and the others decided again without it (at most once per contact).
  const std::vector<Cand> cands = p.cands;
  std::vector<char> dropped(cs_.nc(), 0);
  for (;;) {
    p = Problem{};
    std::vector<int> extra;
    for (const Cand& k : cands) {
      if (dropped[k.c]) continue;
      p.cands.push_back(k);
      extra.insert(extra.end(), cs_[k.c].rough.begin(), cs_[k.c].rough.end());
    }
    if (p.cands.empty()) return true;
    Eigen::MatrixXd J, P;
    Eigen::VectorXd j0, jg, aB;
    rows_of(cs_, p, t, q, qd, J, j0, jg);
    if (contact_inertia(aux_dyn_, cs_, t, q, qd, P, aB, message_, extra) != ModelIssue::none) return false;
    p.W = J * P * J.transpose();
    p.f = J * aB + jg;  // accelerations without contact forces
    LcpSettings settings;
    settings.closed_form_single = !force_lcp && lcp_policy_ == SwitchingOptions::Lcp::several_contacts;
    settings.solver = lcp_solver_;
    Eigen::VectorXd z;
    if (!solve_problem(cs_, p, settings, t, z, lcp_counters_, message_)) return false;
    const Eigen::VectorXd w = p.A * z + p.b;
    const Eigen::VectorXd acc = p.f + p.W * (p.E * z);
    const double scale = 1.0 + p.f.cwiseAbs().maxCoeff() + (p.W * (p.E * z)).cwiseAbs().maxCoeff();
    const double tol = 1e-9 * scale;
    bool again = false;
    for (const Cand& k : p.cands)
      if (!cs_[k.c].rough.empty() && z[k.zn] <= tol && w[k.zn] > tol) {
        dropped[k.c] = 1;
        again = true;
      }
    if (again) continue;
    for (const Cand& k : p.cands) {
      const bool separates = z[k.zn] <= tol && w[k.zn] > tol;
      if (separates) continue;
      if (cs_[k.c].friction < 0) {
        cfg.modes[k.c] = ContactMode::contact;
      } else if (k.frictional) {
        const double zeta = z[k.zn + 3];
        if (zeta <= tol) {
          cfg.modes[k.c] = ContactMode::stick;
        } else if (k.kt2 >= 0) {  // a 2-D cone starts to slide along its tangential acceleration
          cfg.modes[k.c] = ContactMode::slip;
          cfg.sigma[k.c] = 1;
          cfg.dir[k.c] = Eigen::Vector2d(acc[k.kt], acc[k.kt2]).normalized();
        } else {
          cfg.modes[k.c] = ContactMode::slip;
          cfg.sigma[k.c] = acc[k.kt] > 0 ? 1 : -1;
        }
      } else {
        cfg.modes[k.c] = ContactMode::slip;
        cfg.sigma[k.c] = k.sigma;
        cfg.dir[k.c] = k.dir;
      }
    }
    return true;
  }
}

/// Marks the sticking friction rows that depend on the other imposed rows at this state as
/// implied (Huang's rank test, friction rows last). Fails if a normal or bilateral row is
/// itself redundant (contacts that pose the same condition twice).
bool ModeLogic::mark_implied(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg) {
  cfg.implied.assign(cs_.nc(), 0);
  const Layout L = cs_.layout(cfg);
  if (L.imposed.empty()) return true;
  std::vector<int> order;
  for (int i : L.imposed)
    if (!cs_.model().constraints()[i].contact.is_coulomb()) order.push_back(i);
  const int n_plain = static_cast<int>(order.size());
  for (int i : L.imposed)
    if (cs_.model().constraints()[i].contact.is_coulomb()) order.push_back(i);
  const int s = static_cast<int>(order.size());
  Eigen::MatrixXd g(s, cs_.n());
  Eigen::VectorXd g0(s), gamma(s);
  cs_.model().constraint_rows(order, t, q, qd, g, g0, gamma);
  HuangOptions ho;
  ho.kernel = kernel_;
  const HuangResult hr = huang_solve(g, Eigen::VectorXd::Zero(s), ho);
  if (hr.info < 0) {
    message_ = "the Huang kernel rejected the contact rows at t = " + num(t);
    return false;
  }
  if (hr.rank == s) return true;
  for (int r = 0; r < s && r < static_cast<int>(hr.row_dependent.size()); ++r) {
    if (!hr.row_dependent[r]) continue;
    if (r < n_plain) {
      message_ = "the constraint '" + cs_.model().constraints()[order[r]].name +
                 "' depends on the other closed contacts at t = " + num(t) +
                 " (redundant unilateral contacts are not supported)";
      return false;
    }
    const int c = cs_.contact_of_friction(order[r]);
    cfg.implied[c] |= order[r] == cs_[c].friction2 ? 2 : 1;
  }
  return true;
}

/// Checks a configuration at a state: closed contacts push (λ_n > 0), sticking ones inside
/// the cone, sliding ones accelerate along their direction when they start from rest. At a
/// rounding-level tie the first offending contact is switched (closed -> open, stick ->
/// slip) and 1 is returned; 0 when consistent; -1 on failure.
int ModeLogic::check(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg) {
  const Layout L = cs_.layout(cfg);
  Solved s;
  if (solve_reactions(aux_dyn_, cs_, L, cfg, t, q, qd, s, method_) != ModelIssue::none) {
    message_ = aux_dyn_.message().empty() ? message_ : aux_dyn_.message();
    return -1;
  }
  for (int c = 0; c < cs_.nc(); ++c) {
    if (!is_closed(cfg.modes[c])) continue;
    if (!(s.lambda_n[c] > 0.0)) {
      cfg.modes[c] = ContactMode::flight;
      cfg.sigma[c] = 0;
      return 1;
    }
    if (cfg.modes[c] == ContactMode::stick && !(s.friction(c) <= cs_[c].mu_s * s.lambda_n[c])) {
      cfg.modes[c] = ContactMode::slip;
      cfg.sigma[c] = s.lambda_t[c] > 0 && !cs_[c].cone() ? -1 : 1;  // it slides against the force that held it
      if (cs_[c].cone()) {
        if (cfg.dir.size() != static_cast<std::size_t>(cs_.nc())) cfg.dir.assign(cs_.nc(), Eigen::Vector2d::Zero());
        cfg.dir[c] = -Eigen::Vector2d(s.lambda_t[c], s.lambda_t2[c]).normalized();
      }
      return 1;
    }
  }
  return 0;
}

bool ModeLogic::transition(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd, const Config& before,
                           const Solved* reactions_before, Config& after,
                           std::vector<ContactEvent>& events, bool initial) {
  const int nc = cs_.nc();
  std::vector<char> hit(cs_.nc(), 0);
  shares_.begin_instant(nc);
  std::vector<double> vn_b(cs_.nc()), vt_b(cs_.nc());
  for (int c = 0; c < nc; ++c) {
    vn_b[c] = cs_.vn(c, t, q, qd);
    vt_b[c] = cs_[c].cone() ? cs_.speed(c, t, q, qd) : cs_.vt(c, t, q, qd);
  }
  if (!impact_.resolve(t, q, qd, before, events, hit, shares_, message_)) return false;
  bool force_lcp = false;
  for (int attempt = 0;; ++attempt) {
    if (!decide(t, q, qd, after, force_lcp)) return false;
    int fixes = 0, r = 0;
    while (true) {
      if (!mark_implied(t, q, qd, after)) return false;
      r = check(t, q, qd, after);
      if (r != 1 || ++fixes >= 2 * cs_.nc() + 2) break;
    }
    if (r == 0) break;
    if (r < 0 || attempt > 0 || force_lcp) {
      if (r > 0)
        message_ = "no consistent set of contact modes at t = " + num(t) +
                   " (the contacts switch back and forth at one instant)";
      return false;
    }
    force_lcp = true;  // the closed form's choice did not hold: let the LCP decide
  }
  // A friction row whose contact leaves stick loses its position-level constant for good.
  for (int c = 0; c < nc; ++c)
    if (!initial && after.modes[c] != ContactMode::stick) anchored_[c] = 0;
  // Consistent state for the new set: the minimum-norm projection onto the imposed rows.
  const Layout L = cs_.layout(after);
  double dq = 0.0, dv = 0.0;
  std::string msg;
  if (project(L, t, q, qd, dq, dv, msg) != ModelIssue::none) {
    message_ = "projection onto the new contact set at t = " + num(t) + ": " + msg;
    return false;
  }
  // A contact that flies on after the event starts on the surface, not below it. The state
  // at an event lies on the root's far side (the gap a rounding below zero), and the landing
  // threshold of the next flight is taken from where it starts: without this, every bounce
  // started a rounding deeper than the last (the ball 50 m along the floor went 4.8e-6 m into
  // it in 429,062 bounces). The open contacts touching from below (within gap_tol) are
  // projected onto their surface together with the imposed rows, positions only, and the
  // velocities then onto the imposed rows again. Deeper penetrations are left as they are and
  // reported (penetration_max).
  {
    std::vector<int> rows;
    bool lift = false;
    for (int i : L.imposed)
      if (cs_.model().constraints()[i].kind == ConstraintKind::holonomic && position_level(i)) rows.push_back(i);
    for (int c = 0; c < nc; ++c) {
      if (is_closed(after.modes[c])) continue;
      const double gc = cs_.gap(c, t, q);
      if (gc < 0.0 && gc >= -cs_.gap_tol(c, t, q)) {
        rows.push_back(cs_[c].normal);
        lift = true;
      }
    }
    if (lift) {
      Eigen::VectorXd qd_tmp = qd;
      if (project_state(cs_.model(), rows, t, q, qd_tmp, kernel_, projection_tol_, dq, dv, msg, pw_) !=
              ModelIssue::none ||
          project(L, t, q, qd, dq, dv, msg) != ModelIssue::none) {
        message_ = "lifting the rebounding contacts onto their surface at t = " + num(t) + ": " + msg;
        return false;
      }
    }
  }
  for (ContactEvent& ev : events)
    if (ev.t == t && hit[ev.contact]) ev.mode_after = after.modes[ev.contact];
  if (initial) return true;
  // Events of the mode changes that are not impacts.
  for (int c = 0; c < nc; ++c) {
    const ContactMode mb = before.modes[c], ma = after.modes[c];
    if (hit[c]) {
      for (auto it = events.rbegin(); it != events.rend(); ++it)
        if (it->contact == c && it->t == t) {
          it->energy_lost += shares_.pending_loss[c];
          shares_.pending_loss[c] = 0.0;
          break;
        }
      continue;
    }
    ContactEvent ev;
    ev.t = t;
    ev.contact = c;
    ev.constraint = cs_[c].name;
    ev.mode_before = mb;
    ev.mode_after = ma;
    ev.vn_before = vn_b[c];
    ev.vt_before = vt_b[c];
    ev.vn_after = cs_.vn(c, t, q, qd);
    ev.vt_after = cs_[c].cone() ? cs_.speed(c, t, q, qd) : cs_.vt(c, t, q, qd);
    if (shares_.impulsed[c]) {  // switched by an impact elsewhere: the impulse it received
      ev.normal = shares_.impulse_n[c];
      ev.tangential = shares_.impulse_t[c];
    } else if (reactions_before && !reactions_before->lambda_n.empty()) {
      ev.normal = reactions_before->lambda_n[c];
      ev.tangential = cs_[c].cone() ? reactions_before->friction(c) : reactions_before->lambda_t[c];
    }
    if (is_closed(mb) && !is_closed(ma)) {
      ev.kind = ContactEventKind::lift_off;
    } else if (!is_closed(mb) && is_closed(ma)) {
      ev.kind = ContactEventKind::impact;  // touched down without approach velocity
    } else if (mb == ContactMode::stick && ma == ContactMode::slip) {
      ev.kind = ContactEventKind::slip;
    } else if (mb == ContactMode::slip && ma == ContactMode::stick) {
      ev.kind = ContactEventKind::stick;
    } else if (mb == ContactMode::slip && ma == ContactMode::slip && before.sigma[c] != after.sigma[c]) {
      ev.kind = ContactEventKind::reversal;
    } else if (mb == ContactMode::slip && ma == ContactMode::slip && cs_[c].cone() &&
               vt_b[c] <= cs_.vt_tol(c, t, q, qd)) {
      // A 2-D cone that came to rest and slides on in a new direction (its reference direction
      // renewed while it still slides is no event).
      ev.kind = ContactEventKind::reversal;
    } else {
      continue;
    }
    ev.energy_lost = shares_.pending_loss[c];
    shares_.pending_loss[c] = 0.0;
    events.push_back(ev);
  }
  // A closed contact that took part in an impact without a switch of its own: its share of
  // the loss goes to the first impact of the instant.
  for (int c = 0; c < nc; ++c) {
    if (shares_.pending_loss[c] == 0.0) continue;
    for (ContactEvent& ev : events)
      if (ev.t == t && (ev.kind == ContactEventKind::impact || ev.kind == ContactEventKind::accumulation)) {
        ev.energy_lost += shares_.pending_loss[c];
        break;
      }
    shares_.pending_loss[c] = 0.0;
  }
  return true;
}

bool ModeLogic::position_level(int constraint) const {
  const int c = cs_.contact_of_friction(constraint);
  return c < 0 || anchored_[c];
}

ModelIssue ModeLogic::project(const Layout& L, double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                              double& dq, double& dv, std::string& msg) {
  dq = dv = 0.0;
  if (L.imposed.empty()) return ModelIssue::none;
  std::vector<int> pos;
  for (int i : L.imposed)
    if (position_level(i)) pos.push_back(i);
  if (pos.size() == L.imposed.size())
    return project_state(cs_.model(), L.imposed, t, q, qd, kernel_, projection_tol_, dq, dv,
                         msg, pw_);
  if (!pos.empty()) {
    const ModelIssue e = project_state(cs_.model(), pos, t, q, qd, kernel_, projection_tol_,
                                       dq, dv, msg, pw_);
    if (e != ModelIssue::none) return e;
  }
  const int s = static_cast<int>(L.imposed.size());
  pw_.g.resize(s, cs_.n());
  pw_.g0.resize(s);
  pw_.gamma.resize(s);
  cs_.model().constraint_rows(L.imposed, t, q, qd, pw_.g, pw_.g0, pw_.gamma);
  HuangOptions ho;
  ho.kernel = kernel_;
  const HuangResult hr = huang_solve(pw_.g, -(pw_.g * qd + pw_.g0), ho);
  if (hr.info != 0) {
    msg = "the velocity projection onto the contact set failed (Huang info " +
          std::to_string(hr.info) + ")";
    return ModelIssue::inconsistent_constraints;
  }
  qd += hr.x;
  dv += hr.x.norm();
  return ModelIssue::none;
}
}  // namespace pcsim::mech::contacts
