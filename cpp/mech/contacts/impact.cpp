// The impact law: Newton's law with Coulomb friction, the energy rule, accumulation.
#include "mech/contacts/impact.hpp"

#include "mech/projection.hpp"

#include <algorithm>
#include <cmath>

namespace pcsim::mech::contacts {

// The energy rule (issue 19): an impact never creates kinetic energy. Newton's law with
// Coulomb friction can (a corner that must stop sliding while it rebounds: the tangential
// impulse works against the coupling of the normal one; Kane's paradox), and so can Newton's
// law at several contacts. The plastic impact (e = 0) with Coulomb friction never does: by
// complementarity Λ_n v_n⁺ = 0 and Λ_t v_t⁺ = −ζ (β⁺ + β⁻) <= 0, so
// ΔT = Λ·v⁺ − ½ Λ·WΛ <= 0. Where Newton's impulse Λ_N would create energy, the impulse taken
// is Λ_0 + s (Λ_N − Λ_0) with Λ_0 the plastic one and s in [0, 1) the largest with ΔT <= 0:
// it lies in Coulomb's cone (both do, and the cone is convex), no contact approaches after it
// (both leave v_n⁺ >= 0), and it loses no more energy than needed (for e = 1 it conserves
// the energy exactly). Counted in energy_limited_impacts.
bool ImpactLaw::resolve(double t, const Eigen::VectorXd& q, Eigen::VectorXd& qd,
                        const Config& before, std::vector<ContactEvent>& events,
                        std::vector<char>& hit, ImpulseShares& shares, std::string& message) {
  const int nc = cs_.nc();
  Problem p;
  p.impulse = true;
  bool approaching = false;
  std::vector<double> vtol_of(nc, 0.0);
  // Rough rows (ContactInfo::rough) of the touching contacts take part as bilateral rows: a
  // rough landing stops the contact point's sliding in the impact (the perfectly rough impact,
  // Routh's limit of infinite friction). A contact that touches down from a flight with its
  // rough rows moving needs that impulse even without a normal approach.
  std::vector<int> extra;
  bool rough_landing = false;
  for (int c = 0; c < nc; ++c) {
    if (!(cs_.gap(c, t, q) <= cs_.gap_tol(c, t, q))) continue;
    Cand k;
    k.c = c;
    k.frictional = cs_[c].friction >= 0;
    k.mu = cs_[c].mu_k;
    vtol_of[c] = cs_.vn_tol(c, t, q, qd);
    const bool approaches = cs_.vn(c, t, q, qd) < -vtol_of[c];
    // Newton's law v_n⁺ >= −e v_n⁻ restores an approach; a touching contact that does not
    // approach (at rest or separating) only may not be driven into the surface by the others'
    // impulses: v_n⁺ >= 0 (with e, a separating one could have been left approaching at −e v_n⁻).
    k.e = approaches ? cs_[c].e : 0.0;
    p.cands.push_back(k);
    approaching = approaching || approaches;
    for (int i : cs_[c].rough) {
      extra.push_back(i);
      if (!is_closed(before.modes[c])) {
        const Row r = cs_.row(i, t, q, qd);
        rough_landing = rough_landing || std::abs(r.value(qd)) > cs_.velocity_tol(r, qd);
      }
    }
  }
  if (!approaching && !rough_landing) return true;
  Eigen::MatrixXd J, P;
  Eigen::VectorXd j0, jg, aB, dv0;
  rows_of(cs_, p, t, q, qd, J, j0, jg);
  if (contact_inertia(d_, cs_, t, q, qd, P, aB, message, extra, extra.empty() ? nullptr : &dv0) !=
      ModelIssue::none)
    return false;
  const Eigen::MatrixXd M = d_.M;
  // With rough rows: the impulse that brings them to rest first (dv0, the M-weighted projection
  // onto them; it never creates kinetic energy on fixed surfaces), then Newton's law and the
  // energy rule with the rough rows held (Newton bounded by the approach before the impact: a
  // simultaneous rough impact, below).
  const Eigen::VectorXd v_true = J * qd + j0;  // velocities before (reported)
  double dT_rough = 0.0;
  if (!extra.empty()) {
    dT_rough = qd.dot(M * dv0) + 0.5 * dv0.dot(M * dv0);
    qd += dv0;
  }
  p.W = J * P * J.transpose();
  p.f = J * qd + j0;  // velocities before (after the rough impulse)
  // Newton's law refers to the normal velocities before the impact, not to those the rough
  // impulse left: v_n⁺ >= −e v_n⁻ with the rough rows held, the simultaneous rough impact (the
  // impulses of the normal and rough rows solve one system; P imposes the rough rows, so the
  // normal problem sees f = the velocities after their impulse, and −e v_n⁻ as its bound).
  if (!extra.empty()) p.newton_ref = v_true;
  const Eigen::VectorXd v_before = p.f;
  // The change of kinetic energy by the contact impulses Λ, from the velocity change they
  // make (Δq̇ = P Jᵀ Λ): ΔT = q̇⁻ᵀ M Δq̇ + ½ Δq̇ᵀ M Δq̇ + Λ·j0. For scleronomic contacts this is
  // T⁺ − T⁻ (the bilateral constraints' impulses do no work); for a moving surface (j0 ≠ 0)
  // it is the change of the kinetic energy of the motion relative to it, Λ·(v⁻ + v⁺)/2.
  // Computed from Δq̇, not from Λ·WΛ: impulses of redundant contacts can be large and cancel.
  auto energy_change = [&](const Eigen::VectorXd& L, double* round) {
    const Eigen::VectorXd d = P * (J.transpose() * L);
    const Eigen::VectorXd Md = M * d;
    if (round)
      *round = 1e-12 * (qd.cwiseAbs().dot((M.cwiseAbs() * d.cwiseAbs())) +
                        0.5 * d.cwiseAbs().dot(M.cwiseAbs() * d.cwiseAbs()) +
                        L.cwiseAbs().dot(j0.cwiseAbs())) + 1e-300;
    return qd.dot(Md) + 0.5 * d.dot(Md) + L.dot(j0);
  };
  // No touching contact approaches after the impulse (its velocities from Δq̇ as well).
  auto velocities_after = [&](const Eigen::VectorXd& L) -> Eigen::VectorXd {
    return J * (qd + P * (J.transpose() * L)) + j0;
  };
  auto leaves_none_approaching = [&](const Eigen::VectorXd& L) {
    const Eigen::VectorXd v = velocities_after(L);
    for (const Cand& k : p.cands)
      if (!(v[k.kn] >= -vtol_of[k.c])) return false;
    return true;
  };
  const Problem newton = p;  // before assemble(): the plastic problem below starts from it
  Eigen::VectorXd z;
  // With a 2-D cone, Newton's law with restitution may have no solution (no method finds one:
  // three planes wedging the body, the squeeze that Newton's rebound needs outside a cone); the
  // impulse is then the plastic one, as where Newton's impulse leaves a contact approaching
  // (below). Without a cone, and without restitution, no solution is a failure, as before.
  bool cone = false, restitution = false;
  for (const Cand& k : p.cands) {
    cone = cone || k.kt2 >= 0;
    restitution = restitution || k.e > 0.0;
  }
  const bool newton_found = solve_problem(cs_, p, lcp_, t, z, lcp_counters_, message);
  if (!newton_found && !(cone && restitution)) return false;
  if (!newton_found) message.clear();
  Eigen::VectorXd Lam = newton_found ? Eigen::VectorXd(p.E * z) : Eigen::VectorXd::Zero(J.rows());
  // The energy rule.
  bool limited = false;
  double round = 0.0;
  double dT = energy_change(Lam, &round);
  const bool newton_solves = newton_found && leaves_none_approaching(Lam);
  if (dT > round || !newton_solves) {
    Problem plastic = newton;
    for (Cand& k : plastic.cands) k.e = 0.0;
    Eigen::VectorXd z0;
    if (!solve_problem(cs_, plastic, lcp_, t, z0, lcp_counters_, message)) return false;
    const Eigen::VectorXd Lam0 = plastic.E * z0;
    double round0 = 0.0;
    const double dT0 = energy_change(Lam0, &round0);
    if (dT0 > round0 || !leaves_none_approaching(Lam0)) {
      message = "the impact at t = " + num(t) + " (contacts " + names(cs_, p) + ") has no consistent " +
                "solution: the impulses found " +
                (dT0 > round0 ? "would create kinetic energy even without restitution (" + num(dT0) + " J)"
                              : std::string("leave a contact approaching")) +
                " (several contacts that pose dependent conditions, with friction?)";
      return false;
    }
    if (newton_solves) {
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (energy_change(Lam0 + mid * (Lam - Lam0), nullptr) <= 0.0 ? lo : hi) = mid;
      }
      counters_.energy_prevented_max = std::max(counters_.energy_prevented_max, dT);
      Lam = Lam0 + lo * (Lam - Lam0);
    } else {
      Lam = Lam0;  // Newton's impulse is no solution (an LCP answer out of tolerance): plastic
    }
    dT = energy_change(Lam, nullptr);
    limited = true;
    ++counters_.energy_limited;
  }
  Eigen::VectorXd v_after = velocities_after(Lam);
  // Accumulation: a contact that leaves the surface after the impact (a rebound, or a corner
  // lifted by an impact elsewhere) and would land again within zeno_time (2 v_n / |a_n|,
  // a_n with every contact open) starts a sequence of impacts that accumulates; so does a
  // rebound whose apex v_n² / (2 |a_n|) stays below ContactSet::kResolve times the gap's rounding (the
  // flight cannot be resolved: at 50 m from the origin the gap y − 50 is known to 50 eps only,
  // and the landing would be decided by rounding, not by the motion). Its limit is taken at
  // once: every touching contact closed, by the impulse of least kinetic energy that brings
  // their normal velocities to zero (Λ_n = −W_nn⁺ v_n⁻, the P-weighted projection; friction is
  // decided at acceleration level right after).
  bool accumulate = false;
  for (const Cand& k : p.cands) {
    if (!(v_after[k.kn] > vtol_of[k.c])) continue;
    const double an = J.row(k.kn).dot(aB) + jg[k.kn];
    if (!(an < 0.0)) continue;
    const double v = v_after[k.kn];
    if (2.0 * v / -an < zeno_time_ || v * v / (2.0 * -an) < ContactSet::kResolve * cs_.gap_round(k.c, t, q))
      accumulate = true;
  }
  if (accumulate) {
    if (limited) --counters_.energy_limited;  // the closure replaces the limited impulse
    limited = false;
    // First with the sliding velocities of the frictional contacts brought to zero as well
    // (the accumulating impacts end at rest), if the tangential impulses that takes stay in
    // Coulomb's cone (|Λ_t| <= μ_k |Λ_n|); otherwise normals only (a sliding body keeps
    // sliding after its bounces have accumulated).
    for (int with_t = 1; with_t >= 0; --with_t) {
      std::vector<int> rows;
      for (const Cand& k : p.cands) {
        rows.push_back(k.kn);
        if (with_t && k.frictional) rows.push_back(k.kt);
        if (with_t && k.frictional && k.kt2 >= 0) rows.push_back(k.kt2);
      }
      const int m = static_cast<int>(rows.size());
      Eigen::MatrixXd Wr(m, m);
      Eigen::VectorXd vr(m);
      for (int a = 0; a < m; ++a) {
        vr[a] = v_before[rows[a]];
        for (int b = 0; b < m; ++b) Wr(a, b) = p.W(rows[a], rows[b]);
      }
      const Eigen::VectorXd l = -Wr.completeOrthogonalDecomposition().solve(vr);
      Lam.setZero();
      for (int a = 0; a < m; ++a) Lam[rows[a]] = l[a];
      bool in_cone = true;
      for (const Cand& k : p.cands)
        if (with_t && k.frictional)
          in_cone = in_cone && std::hypot(Lam[k.kt], k.kt2 >= 0 ? Lam[k.kt2] : 0.0) <=
                                   cs_[k.c].mu_k * std::abs(Lam[k.kn]) * (1 + 1e-9);
      if (in_cone) break;
    }
    v_after = velocities_after(Lam);
    dT = energy_change(Lam, &round);
    // The least-energy closure: ΔT = −½ v⁻·W⁺v⁻ <= 0 by construction; checked all the same.
    if (dT > round) {
      message = "the accumulation closure at t = " + num(t) + " (contacts " + names(cs_, p) +
                ") would create kinetic energy (" + num(dT) + " J)";
      return false;
    }
  }
  counters_.last_energy_change = dT + dT_rough;
  const Eigen::VectorXd dqd = P * (J.transpose() * Lam);
  bool rough_booked = dT_rough == 0.0;
  for (const Cand& k : p.cands) {
    const double ln = Lam[k.kn];
    const double vb = v_before[k.kn], va = v_after[k.kn];
    double lt = k.kt >= 0 ? Lam[k.kt] : 0.0;
    double vtb = k.kt >= 0 ? v_before[k.kt] : 0.0, vta = k.kt >= 0 ? v_after[k.kt] : 0.0;
    double lost = -0.5 * (ln * (va + vb) + lt * (vta + vtb));
    if (k.kt2 >= 0) {  // a 2-D cone: its share from both rows; reported as magnitudes
      lost -= 0.5 * Lam[k.kt2] * (v_after[k.kt2] + v_before[k.kt2]);
      lt = std::hypot(lt, Lam[k.kt2]);
      vtb = std::hypot(vtb, v_before[k.kt2]);
      vta = std::hypot(vta, v_after[k.kt2]);
    }
    if (!rough_booked && !cs_[k.c].rough.empty()) {  // the rough impulse's loss, to the first rough contact
      lost -= dT_rough;
      rough_booked = true;
    }
    if (!(vb < -vtol_of[k.c])) {
      // A closed contact that took part: its share of the loss is booked with the impact,
      // its impulse reported with its own switch (a lift-off), if any.
      if (ln != 0.0 || lt != 0.0) shares.pending_loss[k.c] += lost;
      shares.impulsed[k.c] = 1;
      shares.impulse_n[k.c] = ln;
      shares.impulse_t[k.c] = lt;
      continue;
    }
    ContactEvent ev;
    ev.t = t;
    ev.kind = accumulate ? ContactEventKind::accumulation : ContactEventKind::impact;
    ev.contact = k.c;
    ev.constraint = cs_[k.c].name;
    ev.mode_before = before.modes[k.c];
    ev.normal = ln;
    ev.tangential = lt;
    ev.vn_before = v_true[k.kn];
    ev.vn_after = va;
    ev.vt_before = vtb;
    ev.vt_after = vta;
    ev.energy_lost = lost;
    ev.energy_limited = limited;
    hit[k.c] = 1;
    events.push_back(ev);
  }
  qd += dqd;
  return true;
}

}  // namespace pcsim::mech::contacts

namespace pcsim::mech {

// ---- resolve_impact (tests of the impact law) -----------------------------------------------------

ImpactOutcome resolve_impact(const Model& model, const std::vector<std::string>& active, double t,
                             const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             const SimulationOptions& options, const SwitchingOptions& switching) {
  ImpactOutcome out;
  std::vector<int> idx;
  std::string msg;
  if (resolve_constraints(model, active, idx, msg) != ModelIssue::none) {
    out.message = msg;
    return out;
  }
  std::string why;
  const contacts::ContactSet cs(model, idx, contacts::Accuracy{options.atol, options.rtol}, why);
  if (!why.empty()) {
    out.message = why;
    return out;
  }
  Dynamics d(model, options.kernel);
  contacts::LcpCounters lcp_counters;
  contacts::ImpactLaw law(
      cs, d, switching.zeno_time,
      contacts::LcpSettings{switching.lcp == SwitchingOptions::Lcp::several_contacts, switching.lcp_solver},
      lcp_counters);
  contacts::ImpulseShares shares;
  shares.begin_instant(cs.nc());
  shares.pending_loss.assign(cs.nc(), 0.0);
  contacts::Config before;
  before.modes.assign(cs.nc(), ContactMode::flight);
  before.sigma.assign(cs.nc(), 0);
  std::vector<char> hit(cs.nc(), 0);
  out.qd_after = qd;
  const bool resolved = law.resolve(t, q, out.qd_after, before, out.events, hit, shares, out.message);
  out.cone_sweeps = lcp_counters.cone_sweeps;
  out.cone_fallbacks = lcp_counters.cone_fallbacks;
  out.cone_unsolved = lcp_counters.cone_unsolved;
  out.cone_newton_steps = lcp_counters.cone_newton_steps;
  if (!resolved) return out;
  out.ok = true;
  out.energy_change = out.events.empty() ? 0.0 : law.counters().last_energy_change;
  out.energy_limited = law.counters().energy_limited;
  return out;
}

}  // namespace pcsim::mech
