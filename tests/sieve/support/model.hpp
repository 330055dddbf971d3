// The vibration sieve as mechanical models (sieve-model.md): the paper's closed form (3.4),
// (3.4a)-(3.4f) with the errata applied, and the geometric form (body positions, springs,
// dampers). Both offer the same constraints and the derived quantity fstar = |R_s| / R_u.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "mech/model.hpp"
#include "sieve/support/settings.hpp"

namespace pcsim::sieve {

using mech::VecX;

/// Which of the equivalent descriptions builds the Model:
/// - geometric: body positions, springs, dampers -> T, V, F; the engine derives M, h, Q by AD.
///   The physical description, independent of the paper's printed formulas.
/// - closed_form: the paper's (3.4) and (3.4a)-(3.4f) (errata applied); M, h by AD. What
///   `pcsim run` integrates (RunOptions::model_form's default).
/// - analytic: the closed form with M, h and Q differentiated by hand (analytic_model.hpp),
///   no AD: ~20x cheaper M, h; an opt-in fast path (C++ API, benchmarks). The tests prove it
///   equal to both AD forms (M, h, Q to 1e-12) and its run equal to the default run.
enum class ModelForm { geometric, closed_form, analytic };
const char* to_string(ModelForm form);

/// Coordinates, constraints and derived quantities shared by both forms.
struct SieveCommon {
  /// Six coordinates (x, y, theta, s, u, phi), known at compile time: the engine's AD then uses
  /// fixed-size derivative vectors, which Eigen unrolls (results bit-identical, ~2x faster).
  static constexpr int kCoordinates = 6;
  SieveParameters p;
  /// Rolling (3.2) is s + r phi = s(0) + r phi(0) (erratum 7: (3.4) measures phi in the sense of
  /// theta, and the contact point lies below the roller's centre, so its velocity along the
  /// deck is s' + r phi'). The paper's printed s - r phi = s(0) - r phi(0) is offered as the
  /// constraint rolling_printed (constraints.rolling_as_printed): a roller turning against the
  /// deck, whose contact point slides at 2 s'.
  double rolling_constant = 0.0;  ///< s(0) + r phi(0)
  double printed_constant = 0.0;  ///< s(0) - r phi(0)

  std::vector<std::string> coordinates() const {
    return {kCoordinateNames.begin(), kCoordinateNames.end()};
  }

  /// contact (3.1) u = u0; rolling (3.2) s + r phi = s(0) + r phi(0) (holonomic);
  /// rolling_velocity, the same in the paper's velocity form g = [0,0,0,1,0,r], g0 = 0;
  /// rolling_printed, the printed s - r phi = s(0) - r phi(0);
  /// lock_theta: theta = 0. Every row is constant.
  std::vector<mech::ConstraintInfo> constraints() const {
    using mech::ConstraintKind;
    return {{"contact", ConstraintKind::holonomic, true},
            {"rolling", ConstraintKind::holonomic, true},
            {"rolling_velocity", ConstraintKind::velocity, true},
            {"lock_theta", ConstraintKind::holonomic, true},
            {"rolling_printed", ConstraintKind::holonomic, true}};
  }

  template <class S> S holonomic(int i, const VecX<S>& q, const S& /*t*/) const {
    switch (i) {
      case 0: return q(4) - p.u0;
      case 1: return q(3) + p.r * q(5) - rolling_constant;
      case 4: return q(3) - p.r * q(5) - printed_constant;
      default: return q(2);  // 3: lock_theta
    }
  }

  template <class S>
  void velocity_form(int /*i*/, const VecX<S>& /*q*/, const S& /*t*/, VecX<S>& g_row,
                     S& g0) const {
    // Only rolling_velocity (index 2) is a velocity-form constraint.
    g_row.setZero();
    g_row(3) = S(1.0);
    g_row(5) = S(p.r);
    g0 = S(0.0);
  }

  std::vector<std::string> derived_names() const { return {"fstar"}; }

  /// fstar = |R_s| / R_u (3.3); +inf when R_u <= 0 (the contact is lost, no friction ratio).
  void derived(double /*t*/, const Eigen::VectorXd& /*q*/, const Eigen::VectorXd& /*qd*/,
               const Eigen::VectorXd& R, Eigen::VectorXd& out) const {
    out.resize(1);
    const double Rs = R(3), Ru = R(4);
    out(0) = Ru > 0 ? std::abs(Rs) / Ru : std::numeric_limits<double>::infinity();
  }
};

/// The paper's model as printed: T is (3.4) with its OCR damage repaired, Q is (3.4a)-(3.4f)
/// with the errata of sieve-model.md section 3 applied; V = F = 0 (everything is in Q).
struct SieveClosedForm : SieveCommon {
  std::string name() const { return "sieve (closed form (3.4))"; }

  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    using std::cos;
    using std::sin;
    const S &th = q(2), &s = q(3), &u = q(4);
    const S &xd = qd(0), &yd = qd(1), &thd = qd(2), &sd = qd(3), &ud = qd(4), &phid = qd(5);
    const double m_all = p.m0 + p.m1 + p.m2;
    const double l0sq = p.x0 * p.x0 + p.y0 * p.y0 + p.e * p.e;  // ℓ0² = x0² + y0² + e²
    const S wt = p.omega * t;
    const S c = cos(th), sn = sin(th);
    const S swt = sin(wt + th), cwt = cos(wt + th);
    const S exc = p.y0 * sin(wt) - p.x0 * cos(wt);  // y0 sin ωt − x0 cos ωt
    S T = 0.5 * m_all * xd * xd + 0.5 * m_all * yd * yd;
    T += 0.5 * (p.J0 + p.J1 + p.J2 + p.m0 * l0sq + 2 * p.m0 * p.e * exc + p.m2 * (s * s + u * u)) *
         thd * thd;
    T += 0.5 * p.m2 * sd * sd + 0.5 * p.m2 * ud * ud + 0.5 * p.J2 * phid * phid;
    // Erratum (3.4): printed "m2 s(cos θ − u sin θ) ẋθ̇", read m2 (s cos θ − u sin θ) ẋθ̇.
    T += (p.m0 * (p.y0 * c - p.x0 * sn + p.e * swt) + p.m2 * (s * c - u * sn)) * xd * thd;
    T += p.m2 * sn * xd * sd + p.m2 * c * xd * ud;
    // Erratum (3.4): printed "m2(sin θ + u cos θ) ẏθ̇", read m2 (s sin θ + u cos θ) ẏθ̇.
    T -= (p.m0 * (p.x0 * c + p.y0 * sn - p.e * cwt) + p.m2 * (s * sn + u * c)) * yd * thd;
    T += p.m2 * c * yd * sd - p.m2 * sn * yd * ud + p.J2 * thd * phid;
    // Erratum (3.4): printed "m0 e w", read m0 e ω.
    T += p.m0 * p.e * p.omega * swt * xd + p.m0 * p.e * p.omega * cwt * yd;
    T += (p.J0 + p.m0 * p.e * exc) * p.omega * thd + 0.5 * p.J0 * p.omega * p.omega;
    T += p.m2 * s * thd * ud - p.m2 * u * thd * sd;
    return T;
  }

  template <class S> S potential_energy(const VecX<S>& /*q*/, const S& /*t*/) const {
    return S(0.0);
  }

  template <class S>
  VecX<S> applied_forces(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    using std::cos;
    using std::sin;
    const S &x = q(0), &y = q(1), &th = q(2), &s = q(3), &u = q(4);
    const S &xd = qd(0), &yd = qd(1), &thd = qd(2);
    const S c = cos(th), sn = sin(th);
    const S wt = p.omega * t;
    const double sigma0 = (p.m0 + p.m1 + p.m2) * p.g / p.cx;  // static spring compression
    const S dx = x + p.yc * sn + p.b * c - p.b;
    const S dy = y - p.xc * sn + p.a * c - p.a;
    const S lx = p.yb * c - p.b * sn;  // vertical damper lever
    const S ly = p.xb * c + p.a * sn;  // horizontal damper lever
    VecX<S> Q(6);
    // (3.4a): gravity and the spring preload cancel (σ0), so they do not appear.
    Q(0) = -p.cx * dx - p.bx * (xd + lx * thd);
    // (3.4b) Erratum: printed "−b_y[ẏ + (x_b cos θ + a sin θ)θ̇]", read "ẏ − (...)θ̇", as in
    // the b_y term of (3.4c).
    Q(1) = -p.cy * dy - p.by * (yd - ly * thd);
    // (3.4c) Errata: "−m1 g[y0 cos θ − ...]" reads −m0 g[...] (the exciter's gravity moment);
    // "−m2 g[s cos θ − u sin θ − b sin θ]" reads −m2 g[s cos θ − u sin θ] (roller at (s, u));
    // the c_y line printed twice with opposite signs is kept once, with the + sign.
    Q(2) = -p.m0 * p.g * (p.y0 * c - p.x0 * sn + p.e * sin(wt + th)) -
           p.m2 * p.g * (s * c - u * sn) - p.ctheta * th -
           p.cx * (dx - sigma0) * (p.yc * c - p.b * sn) + p.cy * dy * (p.xc * c + p.a * sn) -
           p.btheta * thd - p.bx * (xd + lx * thd) * lx + p.by * (yd - ly * thd) * ly;
    Q(3) = -p.m2 * p.g * sn;  // (3.4d)
    Q(4) = -p.m2 * p.g * c;   // (3.4e)
    Q(5) = S(0.0);            // (3.4f)
    return Q;
  }
};

/// The geometric form: positions of the exciter mass, the desk and the roller in the world
/// frame (X up, Y horizontal), the springs and dampers as elements between desk points and the
/// ground; T, V and the Rayleigh function F follow, and the engine derives M, h and Q.
struct SieveGeometric : SieveCommon {
  std::string name() const { return "sieve (geometric)"; }

  /// World position and velocity of a point with desk coordinates (ξ, η) moving relative to
  /// the desk with rates (ξ̇, η̇): X = x + ξ sin θ + η cos θ, Y = y + ξ cos θ − η sin θ.
  template <class S> struct Point { S X, Y, Xd, Yd; };
  template <class S>
  static Point<S> desk_point(const VecX<S>& q, const VecX<S>& qd, const S& xi, const S& eta,
                             const S& xid, const S& etad) {
    using std::cos;
    using std::sin;
    const S c = cos(q(2)), sn = sin(q(2));
    const S& thd = qd(2);
    return {q(0) + xi * sn + eta * c, q(1) + xi * c - eta * sn,
            qd(0) + xid * sn + etad * c + (xi * c - eta * sn) * thd,
            qd(1) + xid * c - etad * sn - (xi * sn + eta * c) * thd};
  }

  /// The unbalanced mass: on the rotor axis at desk point (y0, x0), at radius e and absolute
  /// angle ωt + θ: offset (−e cos(ωt+θ), e sin(ωt+θ)) in the world.
  template <class S> Point<S> exciter_mass(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    using std::cos;
    using std::sin;
    const S zero(0.0);
    Point<S> axis = desk_point<S>(q, qd, S(p.y0), S(p.x0), zero, zero);
    const S psi = p.omega * t + q(2), psid = p.omega + qd(2);
    axis.X -= p.e * cos(psi);
    axis.Y += p.e * sin(psi);
    axis.Xd += p.e * sin(psi) * psid;
    axis.Yd += p.e * cos(psi) * psid;
    return axis;
  }

  template <class S> Point<S> roller_centre(const VecX<S>& q, const VecX<S>& qd) const {
    return desk_point<S>(q, qd, q(3), q(4), qd(3), qd(4));
  }

  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    const Point<S> P0 = exciter_mass(q, qd, t);
    const Point<S> P2 = roller_centre(q, qd);
    const S w0 = p.omega + qd(2);   // rotor absolute angular velocity
    const S w2 = qd(2) + qd(5);     // roller absolute angular velocity
    return 0.5 * p.m0 * (P0.Xd * P0.Xd + P0.Yd * P0.Yd) +
           0.5 * p.m1 * (qd(0) * qd(0) + qd(1) * qd(1)) + 0.5 * p.J1 * qd(2) * qd(2) +
           0.5 * p.J0 * w0 * w0 + 0.5 * p.m2 * (P2.Xd * P2.Xd + P2.Yd * P2.Yd) +
           0.5 * p.J2 * w2 * w2;
  }

  /// Gravity of the three masses plus the three springs. The vertical spring carries the static
  /// preload σ0 = (m0 + m1 + m2) g / cx, so x = 0 is the static equilibrium of the desk.
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    const VecX<S> zero = VecX<S>::Zero(6);
    const S z(0.0);
    const S X0 = exciter_mass(q, zero, t).X;
    const S X2 = roller_centre(q, zero).X;
    // Spring ends: desk points (yc, b) vertical, (a, xc) horizontal; rest positions at θ = 0.
    const S dx = desk_point<S>(q, zero, S(p.yc), S(p.b), z, z).X - p.b;
    const S dy = desk_point<S>(q, zero, S(p.a), S(p.xc), z, z).Y - p.a;
    const double sigma0 = (p.m0 + p.m1 + p.m2) * p.g / p.cx;
    return p.g * (p.m0 * X0 + p.m1 * q(0) + p.m2 * X2) + 0.5 * p.cx * (dx - sigma0) * (dx - sigma0) +
           0.5 * p.cy * dy * dy + 0.5 * p.ctheta * q(2) * q(2);
  }

  /// Rayleigh function of the dampers: vertical at desk point (yb, b), horizontal at (a, xb),
  /// torsional bθ.
  template <class S> S dissipation(const VecX<S>& q, const VecX<S>& qd, const S& /*t*/) const {
    const S z(0.0);
    const S vbx = desk_point<S>(q, qd, S(p.yb), S(p.b), z, z).Xd;
    const S vby = desk_point<S>(q, qd, S(p.a), S(p.xb), z, z).Yd;
    return 0.5 * p.bx * vbx * vbx + 0.5 * p.by * vby * vby + 0.5 * p.btheta * qd(2) * qd(2);
  }
};

/// The Model of a case's sieve in the chosen form (the rolling constant from the initial state).
std::shared_ptr<const mech::Model> make_sieve_model(const SieveSettings& settings,
                                                     ModelForm form = ModelForm::geometric);

/// The names of the active constraints of a case, in row order (contact, rolling, lock_theta);
/// `rolling_velocity` selects the velocity form of (3.2) instead of the holonomic one.
std::vector<std::string> active_constraints(const SieveConstraints& c,
                                            bool rolling_velocity = false);

}  // namespace pcsim::sieve
