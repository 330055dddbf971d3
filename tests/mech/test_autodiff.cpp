// The automatic differentiation of make_model(): M, h, Q, g, g0 and γ = ġq̇ + ġ0 for a
// rheonomic model with damping and both constraint kinds equal their hand-derived closed forms.
#define BOOST_TEST_MODULE mech_autodiff
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "mech/model.hpp"

using namespace pcsim::mech;

namespace {

// A particle in polar coordinates (r, θ) seen from a frame turning at Ω(t) = w0 + w1 t, on a
// radial spring k with a cos θ potential c and radial damping b.
struct RotatingParticle {
  double m = 1.7, k = 3.0, c = 0.8, b = 0.4, w0 = 1.3, w1 = 0.25, a = 0.2, nu = 3.0;
  std::string name() const { return "rotating_particle"; }
  std::vector<std::string> coordinates() const { return {"r", "theta"}; }
  std::vector<ConstraintInfo> constraints() const {
    return {{"breathing", ConstraintKind::holonomic}, {"skew", ConstraintKind::velocity}};
  }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    const S w = qd[1] + w0 + w1 * t;
    return 0.5 * m * (qd[0] * qd[0] + q[0] * q[0] * w * w);
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    using std::cos;
    return 0.5 * k * q[0] * q[0] + c * cos(q[1]);
  }
  template <class S> S dissipation(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * b * qd[0] * qd[0];
  }
  template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const {
    using std::sin;
    return q[0] - (1.0 + a * sin(nu * t));
  }
  template <class S>
  void velocity_form(int i, const VecX<S>& q, const S& t, VecX<S>& g_row, S& g0) const {
    g_row[0] = q[1];
    g_row[1] = q[0];
    g0 = t * t;
  }
};

// A model with only the required members.
struct Minimal {
  std::string name() const { return "minimal"; }
  std::vector<std::string> coordinates() const { return {"x"}; }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * 4.0 * qd[0] * qd[0];
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    return 2.5 * q[0];
  }
};

}  // namespace

// The same model with n known at compile time: the engine then derives M, h by one KineticJet
// sweep instead of the nested AutoDiffScalar sweep.
struct RotatingParticleFixed : RotatingParticle {
  static constexpr int kCoordinates = 2;
};

// A kinetic energy that exercises every KineticJet rule on q̇-dependent operands (products of
// two q̇-dependent factors, division, and sin, cos, tan, exp, log, sqrt of q̇- and
// t-dependent arguments), so both second-order blocks (∂²/∂q̇², ∂²/∂q̇∂ε) pass through the
// chain rule. Not quadratic in q̇; the derivatives are compared, not a physical M.
struct Rich {
  static constexpr int kCoordinates = 3;
  std::string name() const { return "rich"; }
  std::vector<std::string> coordinates() const { return {"a", "b", "c"}; }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    using std::cos;
    using std::exp;
    using std::log;
    using std::sin;
    using std::sqrt;
    using std::tan;
    const S w = qd[0] * cos(q[1]) + qd[1] * sin(0.3 * t + q[2]) - 0.5;
    const S v = qd[2] / (2.0 + q[0] * q[0]) + 0.2 * t;
    return 0.5 * w * w * (1.5 + sin(q[0])) + sqrt(1.0 + v * v) + exp(0.3 * qd[1] * q[2]) +
           log(2.0 + tan(0.2 * qd[0]) * qd[2]) - 1.0 / (3.0 + w * w) + 2.0 * qd[0] * qd[1] * exp(-q[1]) - t * qd[2];
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& /*t*/) const {
    return 0.5 * q[0] * q[0];
  }
};

BOOST_AUTO_TEST_CASE(kinetic_jet_sweep_equals_nested_autodiff_sweep) {
  // Two independent forward-mode implementations (the hand-written KineticJet and Eigen's nested
  // AutoDiffScalar) of the same derivatives, at random states: agreement to 1e-13 relative (the
  // same ~100 operations, rounded in a different order).
  const detail::AutoDiffModel<Rich> model(Rich{});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    Eigen::VectorXd q(3), qd(3);
    for (int i = 0; i < 3; ++i) {
      q[i] = u(rng);
      qd[i] = 0.8 * u(rng);
    }
    const double t = 2.0 * u(rng);
    Eigen::MatrixXd M1(3, 3), M2(3, 3);
    Eigen::VectorXd h1(3), h2(3);
    model.kinetic_terms_jet(t, q, qd, M1, h1);
    model.kinetic_terms_nested(t, q, qd, M2, h2);
    const double sm = M2.cwiseAbs().maxCoeff(), sh = h2.cwiseAbs().maxCoeff();
    BOOST_TEST(sm > 0.1);  // non-trivial: the comparison could fail
    BOOST_TEST(sh > 0.1);
    BOOST_TEST((M1 - M2).cwiseAbs().maxCoeff() <= 1e-13 * sm);
    BOOST_TEST((h1 - h2).cwiseAbs().maxCoeff() <= 1e-13 * sh);
    BOOST_TEST((M1 - M1.transpose()).cwiseAbs().maxCoeff() == 0.0);
  }
}

BOOST_AUTO_TEST_CASE(autodiff_terms_equal_closed_forms_at_random_states) {
  // Closed forms (hand-derived from the energies above), compared to 1e-13 relative: the AD is
  // exact up to roundoff in a few dozen flops. Both derivations: the nested AutoDiffScalar
  // sweep (dynamic n) and the KineticJet sweep (n fixed at compile time).
  for (const bool fixed : {false, true}) {
  const RotatingParticle p;
  const auto model = fixed ? make_model(RotatingParticleFixed{}) : make_model(p);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 25; ++trial) {
    Eigen::VectorXd q(2), qd(2);
    q << 1.0 + 0.5 * u(rng), 3.0 * u(rng);
    qd << u(rng), 2.0 * u(rng);
    const double t = 2.0 * u(rng);
    const double r = q[0], th = q[1], rd = qd[0], thd = qd[1];
    const double W = thd + p.w0 + p.w1 * t;
    Eigen::MatrixXd M(2, 2);
    Eigen::VectorXd h(2), Q(2);
    model->kinetic_terms(t, q, qd, M, h);
    model->forces(t, q, qd, Q);
    const double tol = 1e-13;
    BOOST_TEST(std::abs(M(0, 0) - p.m) < tol * p.m);
    BOOST_TEST(std::abs(M(1, 1) - p.m * r * r) < tol * p.m);
    BOOST_TEST(std::abs(M(0, 1)) < tol * p.m);
    BOOST_TEST(std::abs(M(1, 0)) < tol * p.m);
    const double h_r = -p.m * r * W * W;
    const double h_th = 2.0 * p.m * r * rd * W + p.m * r * r * p.w1;
    BOOST_TEST(std::abs(h[0] - h_r) < tol * (1.0 + std::abs(h_r)));
    BOOST_TEST(std::abs(h[1] - h_th) < tol * (1.0 + std::abs(h_th)));
    const double Q_r = -p.k * r - p.b * rd, Q_th = p.c * std::sin(th);
    BOOST_TEST(std::abs(Q[0] - Q_r) < tol * (1.0 + std::abs(Q_r)));
    BOOST_TEST(std::abs(Q[1] - Q_th) < tol * (1.0 + std::abs(Q_th)));

    Eigen::MatrixXd g(2, 2);
    Eigen::VectorXd g0(2), gamma(2);
    model->constraint_rows({0, 1}, t, q, qd, g, g0, gamma);
    // breathing: Φ = r − 1 − a sin νt → g = (1, 0), g0 = −aν cos νt, γ = aν² sin νt
    BOOST_TEST(g(0, 0) == 1.0);
    BOOST_TEST(g(0, 1) == 0.0);
    BOOST_TEST(std::abs(g0[0] + p.a * p.nu * std::cos(p.nu * t)) < tol);
    BOOST_TEST(std::abs(gamma[0] - p.a * p.nu * p.nu * std::sin(p.nu * t)) < tol * 10.0);
    // skew: g = (θ, r), g0 = t² → γ = θ̇ ṙ + ṙ θ̇ + 2t
    BOOST_TEST(g(1, 0) == th);
    BOOST_TEST(g(1, 1) == r);
    BOOST_TEST(std::abs(g0[1] - t * t) < tol);
    BOOST_TEST(std::abs(gamma[1] - (2.0 * rd * thd + 2.0 * t)) < tol * 10.0);
    BOOST_TEST(std::abs(model->position_residual(0, t, q) -
                        (r - 1.0 - p.a * std::sin(p.nu * t))) < tol);
    BOOST_TEST(std::isnan(model->position_residual(1, t, q)));
  }
  }
}

BOOST_AUTO_TEST_CASE(optional_members_default_to_none) {
  // A model with only the required members: no constraints, no derived quantities, Q = −∂V/∂q.
  const auto model = make_model(Minimal{});
  BOOST_TEST(model->constraints().empty());
  BOOST_TEST(model->derived_names().empty());
  Eigen::MatrixXd M(1, 1);
  Eigen::VectorXd h(1), Q(1);
  model->kinetic_terms(0.0, Eigen::VectorXd::Constant(1, 0.3), Eigen::VectorXd::Constant(1, 1.0), M, h);
  model->forces(0.0, Eigen::VectorXd::Constant(1, 0.3), Eigen::VectorXd::Constant(1, 1.0), Q);
  BOOST_TEST(M(0, 0) == 4.0);
  BOOST_TEST(h[0] == 0.0);
  BOOST_TEST(Q[0] == -2.5);
}
