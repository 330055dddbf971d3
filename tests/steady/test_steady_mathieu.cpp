// The damped Mathieu equation x'' + c x' + (δ + ε cos t) x = 0: the boundary of the first
// instability tongue (a period-4π solution, Floquet multiplier −1) found from pcsim's Floquet
// multipliers of the orbit x = 0 equals
//  - undamped (c = 0): the tabulated characteristic values of the Mathieu equation
//    y'' + (a − 2q cos 2z) y = 0 (t = 2z: a = 4δ, q = −2ε; the tongue is b1(|q|) < a < a1(|q|)),
//    from Abramowitz & Stegun, Table 20.1 (q = 5, 25; the q = 25 values also in Zhang & Jin,
//    "Computation of Special Functions", 1996) and DLMF §28.35's tables (q = 1);
//  - damped: the root of Hill's infinite determinant for 4π-periodic solutions
//    x = Σ a_k cos((2k+1)t/2) + b_k sin((2k+1)t/2), truncated at 40 harmonics and computed here
//    independently of the shooting code.
// The boundary is where det(Φ + I) = 1 + tr Φ + det Φ = 0 (Φ the 2 x 2 monodromy matrix: a
// multiplier −1), found by bisection to 1e-12; tr and det are similarity invariants, so any
// basis of the state space gives them.
#define BOOST_TEST_MODULE steady_mathieu
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <functional>

#include "modelfile/model_file.hpp"
#include "steady/shooting.hpp"

using namespace pcsim;
using namespace pcsim::steady;

namespace {

constexpr double kPi = 3.14159265358979323846;

const char* kMathieu = R"([model]
name = "mathieu"
coordinates = ["x"]
period = "2*pi"

[model.parameters]
delta = 0.25
eps = 0.5
c = 0.0

[model.energy]
kinetic = "0.5*x_d^2"
potential = "0.5*(delta + eps*cos(t))*x^2"
dissipation = "0.5*c*x_d^2"
)";

// 1 + tr Φ + det Φ of the orbit x = 0, and whether pcsim calls the orbit stable.
struct Result {
  double g;
  bool stable;
  double max_modulus;
};

Result floquet_at(double delta, double eps, double c) {
  static const auto d = modelfile::load_model_text(kMathieu, "mathieu.toml");
  OrbitProblem p;
  p.model = d->instantiate({{"delta", delta}, {"eps", eps}, {"c", c}});
  p.period = 2 * kPi;
  ShootingOptions o;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  OrbitPoint x;
  x.y = Eigen::Vector2d(0.0, 0.0);
  const OrbitResult r = find_orbit(p, x, o);
  BOOST_REQUIRE_MESSAGE(r.converged, r.message);
  const Eigen::MatrixXd& M = r.last.monodromy;
  BOOST_REQUIRE(M.rows() == 2);
  return {1.0 + M.trace() + M.determinant(), r.floquet.stable, r.floquet.max_modulus};
}

// The root of f in [lo, hi] (a sign change) by bisection to 1e-12.
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  double flo = f(lo);
  BOOST_REQUIRE_MESSAGE(flo * f(hi) < 0, "no sign change in [" << lo << ", " << hi << "]");
  while (hi - lo > 1e-12) {
    const double mid = 0.5 * (lo + hi), fm = f(mid);
    if ((fm < 0) == (flo < 0)) lo = mid, flo = fm;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Hill's determinant of the 4π-periodic solutions of the damped Mathieu equation, K harmonics.
double hill_determinant(double delta, double eps, double c, int K = 40) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * K, 2 * K);  // unknowns a_0..a_{K-1}, b_0..b_{K-1}
  for (int k = 0; k < K; ++k) {
    const double w = (2 * k + 1) / 2.0;
    // cos(w t): (δ − w²) a_k + c w b_k + ε/2 (a_{k−1} + a_{k+1}), with a_{−1} = a_0
    A(k, k) += delta - w * w;
    A(k, K + k) += c * w;
    if (k + 1 < K) A(k, k + 1) += eps / 2;
    A(k, k > 0 ? k - 1 : 0) += eps / 2;
    // sin(w t): (δ − w²) b_k − c w a_k + ε/2 (b_{k−1} + b_{k+1}), with b_{−1} = −b_0
    A(K + k, K + k) += delta - w * w;
    A(K + k, k) -= c * w;
    if (k + 1 < K) A(K + k, K + k + 1) += eps / 2;
    if (k > 0) A(K + k, K + k - 1) += eps / 2;
    else A(K + k, K) -= eps / 2;
  }
  return A.partialPivLu().determinant();
}

}  // namespace

BOOST_AUTO_TEST_CASE(undamped_tongue_boundary_equals_the_tabulated_characteristic_values) {
  struct Row {
    double q, a1, b1;
  };
  // A&S Table 20.1 (q = 5, 25), DLMF §28.35 (q = 1); 8 or more decimals.
  const Row rows[] = {{1.0, 1.85910807, -0.11024882},
                      {5.0, 1.85818754, -5.79008060},
                      {25.0, -21.31489969, -40.25677898}};
  double worst = 0;
  for (const Row& r : rows) {
    const double eps = r.q / 2;  // |q| = 2 ε
    auto g = [&](double delta) { return floquet_at(delta, eps, 0.0).g; };
    for (double a : {r.b1, r.a1}) {
      const double want = a / 4;
      const double got = bisect(g, want - 0.02, want + 0.02);
      BOOST_TEST_CONTEXT("q = " << r.q << ", a = " << a) {
        // The table's 8 decimals of a, i.e. 2.5e-9 in δ, plus the integration's 1e-12.
        BOOST_TEST(std::abs(got - want) < 3e-9, "boundary " << got << " vs " << want);
      }
      worst = std::max(worst, std::abs(got - want));
    }
    // Between the boundaries the orbit is unstable, outside stable (multipliers on the unit
    // circle: |μ| = 1 to the integration's accuracy).
    const Result mid = floquet_at((r.a1 + r.b1) / 8, eps, 0.0);
    BOOST_TEST(!mid.stable);
    BOOST_TEST(mid.max_modulus > 1.01);
  }
  BOOST_TEST_MESSAGE("undamped tongue boundaries within " << worst << " of the tables (in delta)");
}

BOOST_AUTO_TEST_CASE(damped_tongue_boundary_equals_hills_determinant_and_the_verdict_flips_there) {
  struct Row {
    double eps, c;
  };
  const Row rows[] = {{0.5, 0.05}, {0.5, 0.1}, {2.5, 0.3}};
  double worst = 0;
  for (const Row& r : rows) {
    auto g = [&](double delta) { return floquet_at(delta, r.eps, r.c).g; };
    auto h = [&](double delta) { return hill_determinant(delta, r.eps, r.c); };
    // Damping shrinks the tongue by the factor e^{-c pi} on the multipliers but also shifts it
    // by c²/4 (x = e^{-ct/2} y turns it into an undamped equation with δ − c²/4): scan the
    // undamped edges' neighbourhood (±0.3) for the sign changes of Hill's determinant, then find
    // both roots of each function independently in those brackets.
    const double lo0 = bisect([&](double d) { return floquet_at(d, r.eps, 0.0).g; }, -2.0, 0.25);
    const double hi0 = bisect([&](double d) { return floquet_at(d, r.eps, 0.0).g; }, 0.25, 0.7);
    const double from = lo0 - 0.3, to = hi0 + 0.3;
    double prev = from, fprev = h(from);
    std::vector<std::pair<double, double>> brackets;
    for (int i = 1; i <= 400; ++i) {
      const double d = from + (to - from) * i / 400.0;
      const double fd = h(d);
      if (fd * fprev < 0) brackets.push_back({prev, d});
      prev = d;
      fprev = fd;
    }
    BOOST_TEST_MESSAGE("undamped edges " << lo0 << ", " << hi0 << "; " << brackets.size() << " brackets");
    BOOST_REQUIRE_EQUAL(brackets.size(), 2u);
    for (const auto& [a, b] : brackets) {
      const double hill = bisect(h, a, b);
      const double pcsim = bisect(g, a, b);
      BOOST_TEST_CONTEXT("eps = " << r.eps << ", c = " << r.c) {
        BOOST_TEST(std::abs(pcsim - hill) < 1e-9, "pcsim " << pcsim << ", Hill " << hill);
        // pcsim's verdict flips at the boundary: unstable just inside, stable just outside.
        const bool lower = a < 0.5 * (lo0 + hi0);
        const double inside = lower ? hill + 1e-6 : hill - 1e-6, outside = lower ? hill - 1e-6 : hill + 1e-6;
        BOOST_TEST(!floquet_at(inside, r.eps, r.c).stable);
        BOOST_TEST(floquet_at(outside, r.eps, r.c).stable);
      }
      worst = std::max(worst, std::abs(pcsim - hill));
    }
  }
  BOOST_TEST_MESSAGE("damped tongue boundaries within " << worst << " of Hill's determinant");
}
