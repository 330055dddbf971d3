// The forced Duffing oscillator x'' + c x' + k x + k3 x^3 = F cos(ωt) (tests/steady/duffing.toml):
// pseudo-arclength continuation passes both folds of the bent resonance, the branch between the
// folds is the unstable one, and the orbits at a few ω (all three where three coexist) equal a
// harmonic-balance solution computed here independently, from the equation itself:
// x(θ) = Σ_{j<K} a_j cos((2j+1)θ) + b_j sin((2j+1)θ), θ = ωt (the response of this symmetric
// system has odd harmonics only), K = 25 harmonics, the residual projected onto them by the
// trapezoidal rule at N = 8K points (exact for these trigonometric polynomials: the cubic's
// harmonics up to 3(2K−1) cannot alias onto the unknowns' below N − 3(2K−1)), solved by Newton's
// method to 1e-14. The truncation error of 25 odd harmonics is far below 1e-10 here (the
// coefficients decay by ~10^-2 per harmonic at these amplitudes).
#define BOOST_TEST_MODULE steady_duffing
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "mech/simulation.hpp"
#include "sim/case.hpp"
#include "steady/response.hpp"
#include "steady/steady_case.hpp"

using namespace pcsim;
using namespace pcsim::steady;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double c_ = 0.1, k_ = 1.0, k3_ = 1.0, F_ = 0.5;  // tests/steady/duffing.toml

struct Harmonic {
  Eigen::VectorXd a, b;  // coefficients of cos, sin of the odd harmonics 1, 3, 5, ...
  double omega;
  double x(double th) const {
    double v = 0;
    for (int j = 0; j < a.size(); ++j) v += a[j] * std::cos((2 * j + 1) * th) + b[j] * std::sin((2 * j + 1) * th);
    return v;
  }
  double xth(double th) const {  // dx/dθ
    double v = 0;
    for (int j = 0; j < a.size(); ++j) {
      const double h = 2 * j + 1;
      v += h * (-a[j] * std::sin(h * th) + b[j] * std::cos(h * th));
    }
    return v;
  }
  double xthth(double th) const {
    double v = 0;
    for (int j = 0; j < a.size(); ++j) {
      const double h = 2 * j + 1;
      v -= h * h * (a[j] * std::cos(h * th) + b[j] * std::sin(h * th));
    }
    return v;
  }
};

// Harmonic balance from a guess (which branch: the coefficients of the orbit to compare with).
Harmonic harmonic_balance(double omega, const Harmonic& guess, int K = 25) {
  const int N = 8 * K;
  Harmonic H = guess;
  H.omega = omega;
  for (int it = 0; it < 100; ++it) {
    Eigen::VectorXd R = Eigen::VectorXd::Zero(2 * K);
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * K, 2 * K);
    for (int i = 0; i < N; ++i) {
      const double th = 2 * kPi * i / N;
      const double x = H.x(th);
      const double r = omega * omega * H.xthth(th) + c_ * omega * H.xth(th) + k_ * x + k3_ * x * x * x -
                       F_ * std::cos(th);
      const double dk = k_ + 3 * k3_ * x * x;
      for (int j = 0; j < K; ++j) {
        const double h = 2 * j + 1, cj = std::cos(h * th), sj = std::sin(h * th);
        R[j] += 2.0 / N * r * cj;
        R[K + j] += 2.0 / N * r * sj;
        const double dra = (dk - omega * omega * h * h) * cj - c_ * omega * h * sj;  // ∂r/∂a_j
        const double drb = (dk - omega * omega * h * h) * sj + c_ * omega * h * cj;  // ∂r/∂b_j
        for (int l = 0; l < K; ++l) {
          const double hl = 2 * l + 1, cl = std::cos(hl * th), sl = std::sin(hl * th);
          J(l, j) += 2.0 / N * dra * cl;
          J(K + l, j) += 2.0 / N * dra * sl;
          J(l, K + j) += 2.0 / N * drb * cl;
          J(K + l, K + j) += 2.0 / N * drb * sl;
        }
      }
    }
    const Eigen::VectorXd d = J.fullPivLu().solve(-R);
    H.a += d.head(K);
    H.b += d.tail(K);
    if (d.norm() < 1e-14 * (1 + H.a.norm() + H.b.norm())) return H;
  }
  BOOST_FAIL("harmonic balance did not converge at omega = " << omega);
  return H;
}

// max_θ x(θ): the largest of 4096 samples, refined by Newton on x_θ = 0.
double hb_amplitude(const Harmonic& H) {
  double best = -1e300, th_best = 0;
  for (int i = 0; i < 4096; ++i) {
    const double th = 2 * kPi * i / 4096;
    if (H.x(th) > best) best = H.x(th), th_best = th;
  }
  for (int it = 0; it < 50; ++it) th_best -= H.xth(th_best) / H.xthth(th_best);
  return H.x(th_best);
}

// The Fourier coefficients of a shooting orbit (its x(t) sampled over one period on the
// integrator's dense output): only the guess that selects the branch harmonic balance converges
// on, not part of the comparison.
Harmonic fourier_of_orbit(const OrbitProblem& p, const OrbitPoint& x, int K = 25) {
  const int N = 8 * K;
  const double T = p.period;
  std::vector<double> samples(N, 0.0);
  mech::SimulationOptions so;
  so.t_end = T;
  so.rtol = so.atol = 1e-12;
  so.method = OdeMethod::explicit_rk;
  int next = 0;
  mech::simulate(*p.model, x.y.head(1), x.y.tail(1), so, [&](const mech::StepView& v) {
    while (next < N && T * next / N <= v.t) {
      samples[next] = v.at(T * next / N).q[0];
      ++next;
    }
    return true;
  });
  Harmonic H;
  H.a = Eigen::VectorXd::Zero(K);
  H.b = Eigen::VectorXd::Zero(K);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < K; ++j) {
      H.a[j] += 2.0 / N * samples[i] * std::cos((2 * j + 1) * 2 * kPi * i / N);
      H.b[j] += 2.0 / N * samples[i] * std::sin((2 * j + 1) * 2 * kPi * i / N);
    }
  return H;
}

}  // namespace

BOOST_AUTO_TEST_CASE(continuation_passes_the_folds_and_orbits_equal_harmonic_balance) {
  const sim::Case c = sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/tests/steady/duffing.toml");
  ResponseOptions ro;
  ro.vary = "parameters.omega=0.5:3:26";
  ro.jobs = 2;
  const ResponseResult r = response_case(c, ro);
  BOOST_REQUIRE_MESSAGE(r.complete, r.message);
  const auto& pts = r.points;
  // Two folds: the resonance bends to the right (hardening), so along the branch ω first rises
  // to the upper fold, falls back to the lower one, then rises to the end.
  std::vector<std::size_t> folds;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (pts[i].fold_before) folds.push_back(i);
  BOOST_REQUIRE_EQUAL(folds.size(), 2u);
  const double upper = pts[folds[0]].fold_p, lower = pts[folds[1]].fold_p;
  BOOST_TEST_MESSAGE("folds at omega = " << upper << " and " << lower << "; " << pts.size() << " points");
  BOOST_TEST(upper > lower);
  BOOST_TEST(pts.back().p == 3.0);
  // Stability: stable up to the upper fold, unstable between the folds, stable after the lower
  // one (the multiplier crosses 1 exactly at a fold; the points next to it are decided by the
  // sign of |μ| − 1, checked to be clear of rounding).
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const bool middle = i >= folds[0] && i < folds[1];
    if (std::abs(pts[i].floquet.max_modulus - 1.0) < 1e-6) continue;
    BOOST_TEST_CONTEXT("point " << i << ", omega = " << pts[i].p << ", max |mu| = " << pts[i].floquet.max_modulus)
    BOOST_TEST(pts[i].floquet.stable == !middle);
  }
  // The orbits at chosen ω on every branch through it, against harmonic balance.
  const CaseOrbit base(c, 1, "parameters.omega");
  ShootingOptions so = shooting_options(base.setup(), OdeMethod::automatic);
  int compared = 0;
  double worst_state = 0, worst_amp = 0;
  for (double omega : {1.0, 1.8, 2.0, 2.5}) {
    int found = 0;
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      if ((pts[i].p - omega) * (pts[i + 1].p - omega) > 0) continue;
      const std::size_t near = std::abs(pts[i].p - omega) < std::abs(pts[i + 1].p - omega) ? i : i + 1;
      const OrbitResult o = find_orbit(base.problem(omega), pts[near].x, so);
      BOOST_REQUIRE_MESSAGE(o.converged, o.message);
      ++found;
      // x(0) = Σ a_j, ẋ(0) = ω Σ (2j+1) b_j of the harmonic-balance solution on this branch.
      const Harmonic H = harmonic_balance(omega, fourier_of_orbit(base.problem(omega), o.point));
      double x0 = H.a.sum(), xd0 = 0;
      for (int j = 0; j < H.b.size(); ++j) xd0 += omega * (2 * j + 1) * H.b[j];
      const double scale = std::abs(hb_amplitude(H));
      const double e_state = std::max(std::abs(o.point.y[0] - x0), std::abs(o.point.y[1] - xd0) / omega) / scale;
      // The amplitude as pcsim reports it: the one-period summary's half peak-to-peak of x.
      const CaseOrbit at(case_at(c, "parameters.omega", omega), 1);
      const double amp = period_summary(at, o).extreme("x").amplitude();
      const double e_amp = std::abs(amp - hb_amplitude(H)) / scale;
      BOOST_TEST_CONTEXT("omega = " << omega << ", branch through points " << i << "-" << i + 1) {
        BOOST_TEST(e_state < 1e-6);
        BOOST_TEST(e_amp < 1e-6);
      }
      worst_state = std::max(worst_state, e_state);
      worst_amp = std::max(worst_amp, e_amp);
      ++compared;
    }
    // Three orbits coexist between the folds, one elsewhere.
    BOOST_TEST(found == ((omega > lower && omega < upper) ? 3 : 1), "omega = " << omega << ": " << found << " orbits");
  }
  BOOST_TEST_MESSAGE(compared << " orbits against harmonic balance: state within " << worst_state
                              << ", amplitude within " << worst_amp << " (relative)");
}
