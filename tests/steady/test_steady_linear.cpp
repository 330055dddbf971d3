// Shooting on linear forced systems against their exact solution: the periodic orbit's
// amplitude and phase equal the complex transfer function H(ω) = (K − ω²M + iωC)⁻¹F computed
// from M, C, K directly, and the Floquet multipliers equal exp(λ_i T) of the first-order
// system's eigenvalues; for a free 2-degree-of-freedom oscillator and for the sieve's desk
// linearized about rest with the roller locked (three constraints on six coordinates).
#define BOOST_TEST_MODULE steady_linear
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "modelfile/model_file.hpp"
#include "steady/shooting.hpp"
#include "steady_test_util.hpp"

using namespace pcsim;
using namespace pcsim::steady;
using namespace pcsim::steady::testing;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Linear {
  std::vector<std::string> names;
  Eigen::MatrixXd M, C, K;
  Eigen::VectorXd Fc, Fs;
  std::vector<std::pair<std::string, std::string>> constraints;
  std::vector<int> free;  ///< the coordinates the constraints leave free (the reduced system)
};

// Shoots the orbit of `sys` at omega and compares it with H(ω) and exp(λT). Tolerances: 1e-8
// (the issue's), met with rtol = 1e-12: the integration error of one period is ~1e-11 relative.
void check(const Linear& sys, double omega, double rtol, double atol) {
  const auto d = modelfile::load_model_text(
      linear_model_text(sys.names, sys.M, sys.C, sys.K, sys.Fc, sys.Fs, omega, sys.constraints),
      "linear.toml");
  const int n = static_cast<int>(sys.names.size());
  OrbitProblem p;
  p.model = d->instantiate({});
  for (std::size_t i = 0; i < sys.constraints.size(); ++i) p.active.push_back(static_cast<int>(i));
  p.period = 2 * kPi / omega;
  ShootingOptions o;
  o.rtol = rtol;
  o.atol = atol;
  OrbitPoint guess;
  guess.y = Eigen::VectorXd::Zero(2 * n);
  const OrbitResult r = find_orbit(p, guess, o);
  BOOST_REQUIRE_MESSAGE(r.converged, r.message);
  // The reduced system: the free coordinates' rows and columns.
  const int nf = static_cast<int>(sys.free.size());
  Eigen::MatrixXd Mr(nf, nf), Cr(nf, nf), Kr(nf, nf);
  Eigen::VectorXd Fcr(nf), Fsr(nf);
  for (int a = 0; a < nf; ++a) {
    Fcr[a] = sys.Fc[sys.free[a]];
    Fsr[a] = sys.Fs[sys.free[a]];
    for (int b = 0; b < nf; ++b) {
      Mr(a, b) = sys.M(sys.free[a], sys.free[b]);
      Cr(a, b) = sys.C(sys.free[a], sys.free[b]);
      Kr(a, b) = sys.K(sys.free[a], sys.free[b]);
    }
  }
  const Eigen::VectorXcd Q = transfer(Mr, Cr, Kr, Fcr, Fsr, omega);
  const double scale = Q.cwiseAbs().maxCoeff();
  double amp_err = 0, phase_err = 0;
  for (int a = 0; a < nf; ++a) {
    const int i = sys.free[a];
    // A harmonic q(t) = Re(Q e^{iωt}) has q(0) = Re Q and q̇(0) = −ω Im Q.
    const std::complex<double> got(r.point.y[i], -r.point.y[n + i] / omega);
    amp_err = std::max(amp_err, std::abs(std::abs(got) - std::abs(Q[a])) / scale);
    if (std::abs(Q[a]) > 1e-3 * scale) phase_err = std::max(phase_err, std::abs(std::arg(got / Q[a])));
    BOOST_TEST_CONTEXT("omega = " << omega << ", coordinate " << sys.names[i]) {
      BOOST_TEST(std::abs(std::abs(got) - std::abs(Q[a])) <= 1e-8 * scale);  // amplitude
      if (std::abs(Q[a]) > 1e-3 * scale)
        BOOST_TEST(std::abs(std::arg(got / Q[a])) <= 1e-8);  // phase, rad
    }
  }
  for (int i = 0; i < n; ++i)
    if (std::find(sys.free.begin(), sys.free.end(), i) == sys.free.end())
      BOOST_TEST(std::abs(r.point.y[i]) <= 1e-12 * scale);  // the locked coordinates stay at 0
  std::vector<std::complex<double>> mu;
  for (const auto& f : r.floquet.multipliers) mu.push_back(f.value);
  BOOST_TEST(mu.size() == static_cast<std::size_t>(2 * nf));
  const double dist = set_distance(mu, exact_multipliers(Mr, Cr, Kr, p.period));
  BOOST_TEST(dist <= 1e-8, "Floquet multipliers vs exp(lambda T): " << dist);
  BOOST_TEST_MESSAGE("omega = " << omega << ": " << r.history.size() << " Newton iterations, "
                                << r.steps << " steps; amplitude error " << amp_err
                                << " (relative), phase error " << phase_err
                                << " rad; multipliers within " << dist);
}

}  // namespace

BOOST_AUTO_TEST_CASE(orbit_of_a_linear_oscillator_equals_the_exact_transfer_function) {
  Linear sys;
  sys.names = {"x1", "x2"};
  sys.M.resize(2, 2);
  sys.M << 2.0, 0.3, 0.3, 1.0;
  sys.K.resize(2, 2);
  sys.K << 30.0, -10.0, -10.0, 20.0;
  sys.C.resize(2, 2);
  sys.C << 0.4, -0.1, -0.1, 0.3;
  sys.Fc = Eigen::Vector2d(1.0, 0.0);
  sys.Fs = Eigen::Vector2d(0.5, -2.0);
  sys.free = {0, 1};
  // Below, between, at and above the two resonances (sqrt of the eigenvalues of M⁻¹K: ~2.9, ~5.6).
  for (double omega : {1.0, 2.9, 4.0, 5.6, 9.0}) check(sys, omega, 1e-12, 1e-14);
}

BOOST_AUTO_TEST_CASE(orbit_of_the_linearized_desk_with_the_roller_locked_equals_the_transfer_function) {
  // The sieve's M at rest with the roller at s = 0.4, and K = −∂Q/∂q, C = −∂Q/∂q̇ there (the
  // tape's exact tangents), the excitation's first harmonic from Q − h at rest; the roller is
  // locked by three linear constraints: contact u = 0, rolling s + r phi = 0, hold s = 0.
  const auto sieve = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/models/sieve_1995.toml");
  Eigen::VectorXd q(6), qd = Eigen::VectorXd::Zero(6);
  q << 0, 0, 0, 0.4, 0.15, 0;
  const auto m = sieve->instantiate({}, q, 0.0);
  const double omega = 280.0, T = 2 * kPi / omega;
  Linear sys;
  sys.names = {"x", "y", "theta", "s", "u", "phi"};
  Eigen::VectorXd h(6), Q(6);
  sys.M.resize(6, 6);
  m->kinetic_terms(0.0, q, qd, sys.M, h);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(13, 12), dQ;
  V.topLeftCorner(12, 12).setIdentity();
  m->forces_tangent(0.0, q, qd, V, Q, dQ);
  sys.K = -dQ.leftCols(6);
  sys.C = -dQ.rightCols(6);
  auto f_at = [&](double t) {
    Eigen::MatrixXd Mt(6, 6);
    Eigen::VectorXd ht(6), Qt(6);
    m->kinetic_terms(t, q, qd, Mt, ht);
    m->forces(t, q, qd, Qt);
    return Eigen::VectorXd(Qt - ht);
  };
  const Eigen::VectorXd f0 = f_at(0.0), f2 = f_at(T / 2), f1 = f_at(T / 4);
  sys.Fc = (f0 - f2) / 2;
  sys.Fs = f1 - (f0 + f2) / 2;
  sys.constraints = {{"contact", "u"}, {"rolling", "s + 0.1*phi"}, {"hold", "s"}};
  sys.free = {0, 1, 2};
  for (double w : {60.0, 280.0}) {
    Linear at = sys;
    if (w != omega) {  // the exciter's force scales with ω² (its centrifugal force)
      at.Fc *= (w * w) / (omega * omega);
      at.Fs *= (w * w) / (omega * omega);
    }
    check(at, w, 1e-12, 1e-17);
  }
}
