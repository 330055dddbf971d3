// The contact set: contacts of the active constraints, layouts, kinematics, tolerances.
#include "mech/contacts/contact_set.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "common/format.hpp"
#include "mech/projection.hpp"

namespace pcsim::mech::contacts {

std::string num(double v) { return format_significant(v, 9); }

ContactSet::ContactSet(const Model& model, std::vector<int> active, Accuracy accuracy,
                       std::string& why)
    : model_(model), active_(std::move(active)), acc_(accuracy), n_(model.n()) {
  why.clear();
  for (int i : active_) {
    const ContactInfo& ci = model.constraints()[i].contact;
    if (!ci.unilateral && !ci.is_friction()) bilateral_.push_back(i);
  }
  for (int i : active_) {
    const ConstraintInfo& ci = model.constraints()[i];
    if (!ci.contact.unilateral) continue;
    if (ci.kind != ConstraintKind::holonomic) {
      why = "the unilateral constraint '" + ci.name + "' is not holonomic";
      contacts_.clear();
      return;
    }
    ContactDef d;
    d.normal = i;
    d.sign = ci.contact.gap_sign >= 0 ? 1 : -1;
    d.e = ci.contact.restitution;
    d.name = ci.name;
    contacts_.push_back(d);
  }
  for (int i : active_) {
    const ConstraintInfo& ci = model.constraints()[i];
    if (!ci.contact.is_friction()) continue;
    ContactDef* owner = nullptr;
    for (ContactDef& d : contacts_)
      if (d.normal == ci.contact.friction_of) owner = &d;
    if (!owner) {
      why = "the " + std::string(ci.contact.rough ? "rough" : "friction") + " constraint '" + ci.name +
            "' acts at the unilateral constraint '" + model.constraints()[ci.contact.friction_of].name +
            "', which is not active (activate both, or neither)";
    } else if (ci.contact.rough) {
      if (ci.kind != ConstraintKind::velocity)
        why = "the rough constraint '" + ci.name + "' is not in velocity form";
      owner->rough.push_back(i);
      any_rough_ = true;
    } else if (owner->friction2 >= 0) {
      why = "the unilateral constraint '" + owner->name + "' has three active friction constraints ('" +
            model.constraints()[owner->friction].name + "', '" + model.constraints()[owner->friction2].name +
            "' and '" + ci.name + "'); a contact slides along a line (one friction row) or in a plane (two)";
    } else if (owner->friction >= 0 && (ci.contact.mu_static != owner->mu_s || ci.contact.mu_kinetic != owner->mu_k)) {
      why = "the friction constraints '" + model.constraints()[owner->friction].name + "' and '" + ci.name +
            "' of the unilateral constraint '" + owner->name + "' have different coefficients (mu_static " +
            num(owner->mu_s) + " and " + num(ci.contact.mu_static) + ", mu_kinetic " + num(owner->mu_k) + " and " +
            num(ci.contact.mu_kinetic) + "): the two rows of a 2-D Coulomb cone share one isotropic law";
    }
    if (!why.empty()) {
      contacts_.clear();
      return;
    }
    if (ci.contact.rough) continue;
    // A second friction row makes the contact's cone 2-D: the rows are the sliding velocity's
    // components along orthonormal tangent directions (docs/switching.md "2-D Coulomb cone").
    (owner->friction >= 0 ? owner->friction2 : owner->friction) = i;
    owner->mu_s = ci.contact.mu_static;
    owner->mu_k = ci.contact.mu_kinetic;
  }
  // A contact either rolls perfectly rough (rough rows) or obeys Coulomb's law (one friction
  // row): the switching engine has no law for a rough contact that may also slip.
  for (const ContactDef& d : contacts_)
    if (d.friction >= 0 && !d.rough.empty()) {
      why = "the unilateral constraint '" + d.name + "' has rough rows ('" +
            model.constraints()[d.rough[0]].name + "') and a friction constraint ('" +
            model.constraints()[d.friction].name + "'); activate one kind";
      contacts_.clear();
      return;
    }
}

Layout ContactSet::layout(const Config& cfg) const {
  Layout L;
  std::vector<int> rows;
  L.normal_pos.assign(nc(), -1);
  L.friction_pos.assign(nc(), -1);
  L.friction2_pos.assign(nc(), -1);
  for (int i : active_) {
    const ContactInfo& ci = model_.constraints()[i].contact;
    int c = -1;
    if (ci.unilateral) {
      c = contact_of_normal(i);
      if (!is_closed(cfg.modes[c])) continue;
      L.normal_pos[c] = static_cast<int>(rows.size());
    } else if (ci.rough) {
      c = contact_of_normal(ci.friction_of);
      if (c < 0 || !is_closed(cfg.modes[c])) continue;
    } else if (ci.is_friction()) {
      c = contact_of_friction(i);
      if (c < 0 || cfg.modes[c] != ContactMode::stick) continue;
      const int bit = i == contacts_[c].friction2 ? 2 : 1;
      if (!cfg.implied.empty() && (cfg.implied[c] & bit)) continue;
      (bit == 2 ? L.friction2_pos : L.friction_pos)[c] = static_cast<int>(rows.size());
    }
    rows.push_back(i);
  }
  L.imposed = rows;
  L.s_A = static_cast<int>(rows.size());
  for (int c = 0; c < nc(); ++c) {
    if (cfg.modes[c] == ContactMode::slip) {
      L.friction_pos[c] = static_cast<int>(rows.size());
      rows.push_back(contacts_[c].friction);
      if (contacts_[c].cone()) {
        L.friction2_pos[c] = static_cast<int>(rows.size());
        rows.push_back(contacts_[c].friction2);
      }
    }
  }
  L.set = ActiveSet::of(model_, rows);
  return L;
}

int ContactSet::contact_of_normal(int constraint) const {
  for (int c = 0; c < nc(); ++c)
    if (contacts_[c].normal == constraint) return c;
  return -1;
}

int ContactSet::contact_of_friction(int constraint) const {
  for (int c = 0; c < nc(); ++c)
    if (contacts_[c].friction == constraint || contacts_[c].friction2 == constraint) return c;
  return -1;
}

Row ContactSet::row(int constraint, double t, const Eigen::VectorXd& q,
                    const Eigen::VectorXd& qd) const {
  Eigen::MatrixXd g(1, n_);
  Eigen::VectorXd g0(1), gamma(1);
  model_.constraint_rows({constraint}, t, q, qd, g, g0, gamma);
  Row r;
  r.g = g.row(0);
  r.g0 = g0[0];
  r.gamma = gamma[0];
  return r;
}

Row ContactSet::normal_row(int c, double t, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& qd) const {
  Row r = row(contacts_[c].normal, t, q, qd);
  const double s = contacts_[c].sign;
  r.g *= s;
  r.g0 *= s;
  r.gamma *= s;
  return r;
}

double ContactSet::gap(int c, double t, const Eigen::VectorXd& q) const {
  return contacts_[c].sign * model_.position_residual(contacts_[c].normal, t, q);
}

double ContactSet::vn(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  return normal_row(c, t, q, qd).value(qd);
}

double ContactSet::vt(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  if (contacts_[c].friction < 0) return 0.0;
  return row(contacts_[c].friction, t, q, qd).value(qd);
}

Eigen::Vector2d ContactSet::vt2(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  Eigen::Vector2d v(vt(c, t, q, qd), 0.0);
  if (contacts_[c].cone()) v[1] = row(contacts_[c].friction2, t, q, qd).value(qd);
  return v;
}

double ContactSet::speed(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  return contacts_[c].cone() ? vt2(c, t, q, qd).norm() : std::abs(vt(c, t, q, qd));
}

double ContactSet::row_scale(const Row& r, double t, const Eigen::VectorXd& q) const {
  return r.g.cwiseAbs().dot(q.cwiseAbs()) + std::abs(r.g0 * t);
}

double ContactSet::gap_round(int c, double t, const Eigen::VectorXd& q) const {
  const Row r = normal_row(c, t, q, Eigen::VectorXd::Zero(n_));
  return kRound * kEps * row_scale(r, t, q);
}

double ContactSet::gap_tol(int c, double t, const Eigen::VectorXd& q) const {
  const Row r = normal_row(c, t, q, Eigen::VectorXd::Zero(n_));
  return 10.0 * acc_.atol * r.g.cwiseAbs().sum() + kRound * kEps * row_scale(r, t, q);
}

double ContactSet::velocity_tol(const Row& r, const Eigen::VectorXd& qd) const {
  const double terms = r.g.cwiseAbs().dot(qd.cwiseAbs()) + std::abs(r.g0);
  return 10.0 * (acc_.atol * r.g.cwiseAbs().sum() + acc_.rtol * terms) + kRound * kEps * terms;
}

double ContactSet::vn_tol(int c, double t, const Eigen::VectorXd& q,
                          const Eigen::VectorXd& qd) const {
  return velocity_tol(normal_row(c, t, q, qd), qd);
}

double ContactSet::vt_tol(int c, double t, const Eigen::VectorXd& q,
                          const Eigen::VectorXd& qd) const {
  if (contacts_[c].friction < 0) return 0.0;
  const double t1 = velocity_tol(row(contacts_[c].friction, t, q, qd), qd);
  if (!contacts_[c].cone()) return t1;
  return std::hypot(t1, velocity_tol(row(contacts_[c].friction2, t, q, qd), qd));
}

double ContactSet::velocity_round(const Row& r, const Eigen::VectorXd& qd) const {
  return kRound * kEps * (r.g.cwiseAbs().dot(qd.cwiseAbs()) + std::abs(r.g0));
}

ModelIssue solve_reactions(Dynamics& d, const ContactSet& cs, const Layout& L, const Config& cfg,
                           double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                           Solved& out, ReactionMethod method) {
  ModelIssue e = d.evaluate(L.set, t, q, qd);
  if (e != ModelIssue::none) return e;
  if (L.set.size() == L.s_A) {
    // No sliding contact: exactly the engine's solve of simulate().
    e = d.solve(method);
  } else {
    std::vector<SlidingFriction> sliding;
    for (int c = 0; c < cs.nc(); ++c) {
      if (cfg.modes[c] != ContactMode::slip) continue;
      SlidingFriction sf{L.normal_pos[c], L.friction_pos[c], cs[c].mu_k * cfg.sigma[c] * cs[c].sign};
      if (cs[c].cone()) {
        // A 2-D cone: the friction force −μ_k λ_n v/|v| along the sliding velocity v = (v_t1,
        // v_t2); while |v| is at rounding level (a slide that starts from rest) along the
        // segment's direction, which v/|v| approaches continuously.
        sf.friction_row2 = L.friction2_pos[c];
        // The two friction rows as evaluate() has just formed them (rows friction_pos and
        // friction2_pos of the active set); evaluated again only where evaluate() kept them
        // sparse.
        Row r1, r2;
        if (d.sparse_evaluated()) {
          r1 = cs.row(cs[c].friction, t, q, qd);
          r2 = cs.row(cs[c].friction2, t, q, qd);
        } else {
          r1.g = d.g.row(L.friction_pos[c]);
          r1.g0 = d.g0[L.friction_pos[c]];
          r2.g = d.g.row(L.friction2_pos[c]);
          r2.g0 = d.g0[L.friction2_pos[c]];
        }
        Eigen::Vector2d v(r1.value(qd), r2.value(qd));
        // Past the segment's event (v behind its reference direction: the integrator's stages
        // beyond a stop) the velocity is mirrored across the line normal to the reference: the
        // force then continues smoothly (a slide that stops along a line keeps its direction, as
        // the 1-D law keeps sigma), so the step that holds the stop is integrated accurately.
        const Eigen::Vector2d ref = static_cast<std::size_t>(c) < cfg.dir.size() ? cfg.dir[c] : Eigen::Vector2d::Zero();
        const double along = v.dot(ref);
        if (along < 0.0) v -= 2.0 * along * ref;
        const double vr = cs.velocity_round(r1, qd) + cs.velocity_round(r2, qd);
        const double len = v.norm();
        if (len > vr)
          v /= len;
        else
          v = static_cast<std::size_t>(c) < cfg.dir.size() ? cfg.dir[c] : Eigen::Vector2d(1.0, 0.0);
        sf.coefficient = cs[c].mu_k * cs[c].sign;
        sf.w1 = v[0];
        sf.w2 = v[1];
      }
      sliding.push_back(sf);
    }
    e = d.solve_sliding(method, L.s_A, sliding);
  }
  if (e != ModelIssue::none) return e;
  out.qdd = d.qdd;
  out.R = d.R;
  out.lambda = d.lambda.head(L.s_A);
  out.lambda_set = d.lambda.head(L.set.size());
  out.lambda_n.assign(cs.nc(), 0.0);
  out.lambda_t.assign(cs.nc(), 0.0);
  out.lambda_t2.assign(cs.nc(), 0.0);
  for (int c = 0; c < cs.nc(); ++c) {
    if (L.normal_pos[c] < 0) continue;
    out.lambda_n[c] = cs[c].sign * out.lambda[L.normal_pos[c]];
    if (cfg.modes[c] == ContactMode::stick && L.friction_pos[c] >= 0)
      out.lambda_t[c] = out.lambda[L.friction_pos[c]];
    if (cfg.modes[c] == ContactMode::stick && L.friction2_pos[c] >= 0)
      out.lambda_t2[c] = out.lambda[L.friction2_pos[c]];
    if (cfg.modes[c] == ContactMode::slip && !cs[c].cone())
      out.lambda_t[c] = -cs[c].mu_k * cfg.sigma[c] * out.lambda_n[c];
    if (cfg.modes[c] == ContactMode::slip && cs[c].cone()) {
      out.lambda_t[c] = d.lambda[L.friction_pos[c]];
      out.lambda_t2[c] = d.lambda[L.friction2_pos[c]];
    }
  }
  return ModelIssue::none;
}

}  // namespace pcsim::mech::contacts

namespace pcsim::mech {

const char* to_string(ContactMode mode) {
  switch (mode) {
    case ContactMode::flight: return "flight";
    case ContactMode::contact: return "contact";
    case ContactMode::stick: return "stick";
    case ContactMode::slip: return "slip";
  }
  return "unknown";
}

const char* to_string(ContactEventKind kind) {
  switch (kind) {
    case ContactEventKind::lift_off: return "lift_off";
    case ContactEventKind::impact: return "impact";
    case ContactEventKind::accumulation: return "accumulation";
    case ContactEventKind::slip: return "slip";
    case ContactEventKind::stick: return "stick";
    case ContactEventKind::reversal: return "reversal";
  }
  return "unknown";
}

std::ostream& operator<<(std::ostream& os, ContactMode mode) { return os << to_string(mode); }
std::ostream& operator<<(std::ostream& os, ContactEventKind kind) { return os << to_string(kind); }

std::vector<std::string> unilateral_constraints(const Model& model,
                                                const std::vector<std::string>& active) {
  std::vector<std::string> out;
  for (const ConstraintInfo& c : model.constraints())
    if (c.contact.unilateral && std::find(active.begin(), active.end(), c.name) != active.end())
      out.push_back(c.name);
  return out;
}

// ---- switching_reactions (tests of the two formulations) ------------------------------------------

ReactionResult switching_reactions(const Model& model, const std::vector<std::string>& active,
                                   const std::vector<ContactMode>& modes,
                                   const std::vector<int>& slip_sign, double t,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   ReactionMethod method, Kernel kernel) {
  ReactionResult out;
  std::vector<int> idx;
  std::string msg;
  if (const ModelIssue e = resolve_constraints(model, active, idx, msg); e != ModelIssue::none) {
    out.issue = e;
    out.message = msg;
    return out;
  }
  std::string why;
  const contacts::ContactSet cs(model, idx, contacts::Accuracy{}, why);
  if (!why.empty()) {
    out.issue = ModelIssue::unknown_constraint;
    out.message = why;
    return out;
  }
  if (modes.size() != static_cast<std::size_t>(cs.nc()) ||
      slip_sign.size() != static_cast<std::size_t>(cs.nc())) {
    out.issue = ModelIssue::unknown_constraint;
    out.message = "switching_reactions: one mode and one slip sign per unilateral constraint";
    return out;
  }
  contacts::Config cfg;
  cfg.modes = modes;
  cfg.sigma = slip_sign;
  const contacts::Layout L = cs.layout(cfg);
  contacts::Solved s;
  Dynamics d(model, kernel);
  const ModelIssue e = contacts::solve_reactions(d, cs, L, cfg, t, q, qd, s, method);
  if (e != ModelIssue::none) {
    out.issue = e;
    out.message = d.message();
    return out;
  }
  out.R = s.R;
  out.qdd = s.qdd;
  out.lambda = s.lambda;
  return out;
}

}  // namespace pcsim::mech
