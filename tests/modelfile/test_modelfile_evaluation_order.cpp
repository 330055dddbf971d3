// The tape evaluates the expressions as written (and as differentiation makes them), never an
// expansion that cancels catastrophically (issue 19, "Expanded polynomials lose all accuracy").
// Oracles: exact rational arithmetic (GiNaC numerics on the exact values of the doubles the
// tape sees, the derivatives formed by hand) and an independent quadrature of a 1-DOF energy
// integral. The error bounds are those of the expressions themselves: x - a of two doubles is
// exact or carries one rounding, and each further multiplication or power step adds at most
// about u = 2^-53, so a product of powers of offset differences is right to (number of
// operations) u relative however far x and a sit from the origin; a sum adds u times
// Σ|terms| / |sum| (its own conditioning). The expanded polynomial's error is u times
// Σ|monomials| / |result|: 1e10 to 1e40 at the states below. The same model gives the same
// tape and the same bits in every process.
#define BOOST_TEST_MODULE modelfile_evaluation_order
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <random>
#include <sstream>
#include <vector>

#include <ginac/ginac.h>

#include "../support/cli_util.hpp"
#include "modelfile/expression.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;
using GiNaC::numeric;

namespace {

constexpr double u = 0x1p-53;  // unit roundoff of double

std::shared_ptr<const ModelDescription> load(const std::string& text) {
  return load_model_text(text, "evaluation_order.toml");
}

// The exact value of a double, as a rational.
numeric exact(double v) {
  if (v == 0.0) return 0;
  int e = 0;
  const double m = std::frexp(v, &e);  // v = m 2^e, 0.5 <= |m| < 1
  const auto mant = static_cast<long long>(std::ldexp(m, 53));
  return numeric(mant) * numeric(2).power(numeric(e - 53));
}

// |x - exact| / |exact| (x a double).
double rel_error(double x, const numeric& ex) {
  if (ex.is_zero()) return x == 0.0 ? 0.0 : INFINITY;
  return std::abs(((exact(x) - ex) / ex).to_double());
}

// A double printed so that it reads back exactly.
std::string text_of(double v);
std::string text(double v) { return text_of(v); }
std::string text_of(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

struct Values {
  Eigen::MatrixXd M;
  Eigen::VectorXd h, Q, out;
};
Values values(const mech::Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const int n = m.n();
  Values v;
  v.M.resize(n, n);
  v.h.resize(n);
  v.Q.resize(n);
  v.out.resize(static_cast<int>(m.derived_names().size()));
  m.kinetic_terms(0.0, q, qd, v.M, v.h);
  m.forces(0.0, q, qd, v.Q);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  m.derived(0.0, q, qd, zero, zero, v.out);
  return v;
}

// States x0 + δ around an offset: near (exact differences), far, and past the origin.
std::vector<double> offsets_from(double x0) {
  return {x0 + 1e-3, x0 - 7.5e-4, x0 + 0.0123, x0 - 0.5, x0 + 3.7, x0 - 250.0, x0 + 1e4,
          x0 * (1 + 1e-9), x0 * (1 - 3e-12), -x0 + 2.5};
}

}  // namespace

// The spring: k (x - x0)^3 with x0 = 1000 as a force, as the derivative of the
// potential k (x - x0)^4 / 4, with x0 a parameter and a literal. F = -k (x - x0)^3 has the
// relative condition 3 in x - x0; evaluated so, its error is at most ~6u (one rounding of
// x - x0 when not exact, two for the cube, one for k). The expanded cubic had 1513.
BOOST_AUTO_TEST_CASE(cubic_spring_far_from_the_origin_is_right_to_a_few_ulps) {
  const std::string head = "[model]\nname = \"spring\"\ncoordinates = [\"x\"]\n"
                           "[model.parameters]\nk = 2.5\nx0 = 1000.0\n"
                           "[model.energy]\nkinetic = \"0.5*x_d^2\"\n";
  const std::vector<std::string> variants = {
      head + "[model.forces]\nx = \"-k*(x - x0)^3\"\n",
      head + "potential = \"k*(x - x0)^4/4\"\n",
      head + "potential = \"k*(x - 1000)^4/4\"\n",
      head + "potential = \"2.5*(1000 - x)^4/4\"\n",
      head + "[model.forces]\nx = \"-(x - x0)^3*k\"\n[model.outputs]\nF = \"-k*(x - x0)^3\"\n"};
  double worst = 0.0;
  for (const std::string& file : variants) {
    const auto d = load(file);
    const auto m = d->instantiate({});
    for (double x : offsets_from(1000.0)) {
      Eigen::VectorXd q(1), qd(1);
      q << x;
      qd << 0.0;
      const Values v = values(*m, q, qd);
      const numeric dx = exact(x) - numeric(1000);
      const numeric F = -numeric(5, 2) * dx * dx * dx;
      const double e = rel_error(v.Q[0], F);
      worst = std::max(worst, e);
      BOOST_TEST(e <= 6 * u, "x = " << text(x) << ": Q = " << text(v.Q[0]) << ", relative error "
                                    << e << " (" << file << ")");
      for (int i = 0; i < v.out.size(); ++i) BOOST_TEST(rel_error(v.out[i], F) <= 6 * u);
    }
  }
  std::printf("cubic spring at x0 = 1000: worst relative error %.3g (u = %.3g)\n", worst, u);
}

// (x - 1)^30 at x = 1.1 is 1e-30 (exactly (1.1 - 1)^30 for the double 1.1, x - 1 being
// exact): powering by squaring has a relative error of at most (n - 1)u (each squaring
// doubles the error so far), so n u bounds it; in practice it is a few ulps. The expanded
// polynomial gave -5e-8, and (x - 1)^60 gave 127.7. Also as the force of the potential
// (x - 1)^(n+1)/(n+1), and at other states.
BOOST_AUTO_TEST_CASE(high_powers_of_an_offset_difference_keep_their_digits) {
  double worst_ulps = 0.0;
  for (int n : {30, 44, 60, 99}) {
    std::ostringstream f;
    f << "[model]\nname = \"powers\"\ncoordinates = [\"x\"]\n[model.energy]\n"
      << "kinetic = \"0.5*x_d^2\"\npotential = \"(x - 1)^" << n + 1 << "/" << n + 1 << "\"\n"
      << "[model.outputs]\np = \"(x - 1)^" << n << "\"\nq = \"(1 - x)^" << n << "*3 + x - x\"\n";
    const auto m = load(f.str())->instantiate({});
    for (double x : {1.1, 0.9, 1.0 + 1e-3, 1000.5, 1.0 - 0.37}) {
      Eigen::VectorXd q(1), qd(1);
      q << x;
      qd << 0.0;
      const Values v = values(*m, q, qd);
      const numeric p = (exact(x) - 1).power(n);
      const double bound = n * u;
      worst_ulps = std::max(worst_ulps, rel_error(v.out[0], p) / u);
      if (x == 1.1 && (n == 30 || n == 60)) {
        // The examples: 1e-30 and 1e-60 to a few ulps (squaring: 1.0 and 1.4 u here).
        BOOST_TEST(rel_error(v.out[0], p) <= 4 * u, "(x-1)^" << n << " at 1.1 = " << text(v.out[0]));
        std::printf("(x - 1)^%d at x = 1.1: %.17g, error %.2f u\n", n, v.out[0],
                    rel_error(v.out[0], p) / u);
      }
      BOOST_TEST(rel_error(v.out[0], p) <= bound, "(x-1)^" << n << " at " << text(x) << " = "
                                                           << text(v.out[0]));
      BOOST_TEST(rel_error(v.out[1], numeric(3) * (1 - exact(x)).power(n)) <= bound + 2 * u);
      BOOST_TEST(rel_error(v.Q[0], -p) <= bound + 2 * u, "Q of (x-1)^" << n + 1 << "/" << n + 1
                                                                   << " at " << text(x) << " = "
                                                                   << text(v.Q[0]));
    }
  }
  std::printf("(x - 1)^n, n up to 99: worst error %.2f u\n", worst_ulps);
}

// Kinetic energies with offset positions: M and h keep the structure as well,
// T = 1/2 (1 + (x - 1000)^2) x_d^2: M = 1 + (x - 1000)^2, h = (x - 1000) x_d^2.
BOOST_AUTO_TEST_CASE(mass_matrix_and_h_of_offset_coordinates) {
  const auto m = load("[model]\nname = \"offset_mass\"\ncoordinates = [\"x\"]\n"
                      "[model.energy]\nkinetic = \"0.5*(1 + (x - 1000)^2)*x_d^2\"\n")
                     ->instantiate({});
  for (double x : offsets_from(1000.0)) {
    Eigen::VectorXd q(1), qd(1);
    q << x;
    qd << 0.37;
    const Values v = values(*m, q, qd);
    const numeric dx = exact(x) - 1000;
    BOOST_TEST(rel_error(v.M(0, 0), 1 + dx * dx) <= 4 * u);
    BOOST_TEST(rel_error(v.h[0], dx * exact(0.37) * exact(0.37)) <= 6 * u,
               "h at " << text(x) << " = " << text(v.h[0]));
  }
}

// A generated family: potentials V = Σ_i c_i Π_j (x_j - a_j)^(n_ij) in three coordinates at
// offsets a_j of 1e3 to 1e6 (exact doubles, written as parameters or as literals), powers up
// to 17, at states within 1e-9 to 1e-1 (relative) of the offsets. Each term's value is right
// to (its operation count) u; the sum adds its own conditioning. Checked: V (an output) and
// Q = -∂V/∂x (formed here by the product rule in exact arithmetic).
BOOST_AUTO_TEST_CASE(generated_offset_polynomials_match_exact_rational_arithmetic) {
  std::mt19937 rng(19);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  int checked = 0;
  double worst_ratio = 0.0;  // error / bound
  for (int model = 0; model < 40; ++model) {
    const int n = 3, terms = pick(1, 4);
    std::vector<double> a(n);
    for (int j = 0; j < n; ++j) {
      const double mag = std::pow(10.0, 3 + pick(0, 3));
      a[j] = (pick(0, 1) ? 1 : -1) * (mag * pick(1, 9) + pick(0, 7) / 8.0);
    }
    const bool literal = model % 2 == 1;
    std::vector<int> c(terms);
    std::vector<std::vector<int>> p(terms, std::vector<int>(n, 0));
    std::ostringstream V;
    for (int i = 0; i < terms; ++i) {
      c[i] = pick(1, 9) * (pick(0, 1) ? 1 : -1);
      V << (i ? " + " : "") << c[i];
      for (int j = 0; j < n; ++j) {
        p[i][j] = pick(0, 17);
        if (p[i][j] == 0) continue;
        const std::string off = literal ? "(" + text(a[j]) + ")" : "a" + std::to_string(j);
        V << "*(q" << j << " - " << off << ")";
        if (p[i][j] > 1) V << "^" << p[i][j];
      }
    }
    std::ostringstream f;
    f << "[model]\nname = \"family\"\ncoordinates = [\"q0\", \"q1\", \"q2\"]\n[model.parameters]\n";
    for (int j = 0; j < n; ++j) f << "a" << j << " = " << text(a[j]) << "\n";
    f << "[model.energy]\nkinetic = \"0.5*(q0_d^2 + q1_d^2 + q2_d^2)\"\npotential = \"" << V.str()
      << "\"\n[model.outputs]\nV = \"" << V.str() << "\"\n";
    const auto m = load(f.str())->instantiate({});
    for (int s = 0; s < 5; ++s) {
      Eigen::VectorXd q(n), qd = Eigen::VectorXd::Zero(n);
      for (int j = 0; j < n; ++j) {
        q[j] = a[j] * (1 + (pick(0, 1) ? 1 : -1) * pick(1, 9) * std::pow(10.0, -pick(1, 9)));
      }
      const Values v = values(*m, q, qd);
      std::vector<numeric> dx(n);
      for (int j = 0; j < n; ++j) dx[j] = exact(q[j]) - exact(a[j]);
      // V and its terms, exactly; each term's operation count.
      numeric Vx = 0, Vabs = 0;
      std::vector<numeric> term(terms);
      int ops = 0;
      for (int i = 0; i < terms; ++i) {
        term[i] = c[i];
        int k = 1;
        for (int j = 0; j < n; ++j) {
          term[i] *= dx[j].power(p[i][j]);
          k += p[i][j] > 0 ? 2 * p[i][j] + 1 : 0;  // (x - a) rounded, raised, multiplied
        }
        ops = std::max(ops, k);
        Vx += term[i];
        Vabs += GiNaC::abs(term[i]);
      }
      const double boundV =
          (ops + terms + 2) * u * (Vx.is_zero() ? 1.0 : (Vabs / GiNaC::abs(Vx)).to_double());
      const double eV = rel_error(v.out[0], Vx);
      BOOST_TEST(eV <= boundV, "model " << model << " V = " << V.str() << " error " << eV
                                        << " bound " << boundV);
      worst_ratio = std::max(worst_ratio, eV / boundV);
      for (int j = 0; j < n; ++j) {
        numeric Q = 0, Qabs = 0;
        for (int i = 0; i < terms; ++i) {
          if (p[i][j] == 0) continue;
          const numeric t = term[i] * p[i][j] / dx[j];
          Q -= t;
          Qabs += GiNaC::abs(t);
        }
        if (Q.is_zero()) {
          BOOST_TEST(v.Q[j] == 0.0);
          continue;
        }
        const double boundQ = (ops + terms + 4) * u * (Qabs / GiNaC::abs(Q)).to_double();
        const double eQ = rel_error(v.Q[j], Q);
        BOOST_TEST(eQ <= boundQ, "model " << model << " Q" << j << " of V = " << V.str()
                                           << " error " << eQ << " bound " << boundQ);
        worst_ratio = std::max(worst_ratio, eQ / boundQ);
        ++checked;
      }
    }
  }
  std::printf("generated offset polynomials: %d forces checked, worst error/bound %.3g\n", checked,
              worst_ratio);
}

// The issue's smooth potential V = (x-1)^2/2 + (x-1)^44 ("more than 1000000 steps ... at
// t = 0" before) runs from the shell to the end, exit 0. Checked against an independent
// integration of the motion: the energy E = x_d^2/2 + V(x) stays constant along the stored
// time series, and the period (from the upward crossings of x = 1) equals the quadrature of
// the energy integral T = 4 ∫_0^{π/2} dθ / sqrt(1 + 2 A^42 Σ_{k=0}^{21} sin^{2k} θ) (from
// x = 1 + A sin θ; V is even about 1, so the turning points are 1 ± A).
BOOST_AUTO_TEST_CASE(the_smooth_potential_with_a_44th_power_runs_and_moves_right) {
  pcsim_test::TempDir dir("evalorder44");
  {
    std::ofstream m(dir.path / "p44.toml");
    m << "[model]\nname = \"p44\"\ncoordinates = [\"x\"]\n[model.energy]\n"
         "kinetic = \"0.5*x_d^2\"\npotential = \"(x - 1)^2/2 + (x - 1)^44\"\n";
  }
  for (double A : {0.5, 1.0}) {
    {
      std::ofstream c(dir.path / "p44_case.toml");
      c << "model = \"p44.toml\"\n[initial]\nx = " << text(1 + A)
        << "\n[solver]\nt_end = 20.0\nrtol = 1e-10\natol = 1e-12\n[output]\ndt = 1e-3\n";
    }
    const auto r = pcsim_test::sh(pcsim_test::exe() + " run p44_case.toml --out out_p44", dir.path);
    BOOST_TEST_REQUIRE(r.status == 0, r.out);
    std::istringstream csv(pcsim_test::read(dir.path / "out_p44" / "timeseries.csv"));
    std::string line;
    std::getline(csv, line);
    BOOST_TEST_REQUIRE(line.rfind("t,x,x_d", 0) == 0u, line);
    auto V = [](double x) { return 0.5 * (x - 1) * (x - 1) + std::pow(x - 1, 44); };
    const double E0 = V(1 + A);
    double drift = 0.0, t_prev = 0.0, y_prev = A, t_end = 0.0;
    std::vector<double> ups;
    while (std::getline(csv, line)) {
      double t = 0, x = 0, xd = 0;
      BOOST_TEST_REQUIRE(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &x, &xd) == 3, line);
      drift = std::max(drift, std::abs(0.5 * xd * xd + V(x) - E0) / E0);
      const double y = x - 1;
      if (y_prev < 0 && y >= 0) ups.push_back(t_prev + (t - t_prev) * (-y_prev) / (y - y_prev));
      t_prev = t;
      y_prev = y;
      t_end = t;
    }
    BOOST_TEST(t_end == 20.0);
    BOOST_TEST(drift < 1e-7, "A = " << A << ": energy drift " << drift);
    // The period by quadrature (composite Simpson on a smooth integrand).
    const int N = 20000;
    double S = 0;
    for (int i = 0; i <= N; ++i) {
      const double th = M_PI / 2 * i / N, s2 = std::sin(th) * std::sin(th);
      double sum = 0, pw = 1;
      for (int k = 0; k <= 21; ++k, pw *= s2) sum += pw;
      const double f = 1 / std::sqrt(1 + 2 * std::pow(A, 42) * sum);
      S += f * (i == 0 || i == N ? 1 : (i % 2 ? 4 : 2));
    }
    const double T = 4 * S * (M_PI / 2 / N) / 3;
    BOOST_TEST_REQUIRE(ups.size() >= 2u);
    const double measured = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
    BOOST_TEST(std::abs(measured - T) / T < 1e-5,
               "A = " << A << ": period " << measured << " vs quadrature " << T);
    std::printf("(x-1)^2/2 + (x-1)^44, amplitude %g: period %.9f (quadrature %.9f), energy drift "
                "%.2g\n", A, measured, T, drift);
  }
}

// The same model file gives the same tape and bit-identical results in separate processes
// (GiNaC's internal order of sums and products differs between processes; the tape must not).
// Two runs of a model whose sums mix terms of very different sizes, in fresh processes.
BOOST_AUTO_TEST_CASE(the_same_file_gives_the_same_bits_in_every_process) {
  pcsim_test::TempDir dir("evalorder_det");
  {
    std::ofstream m(dir.path / "mix.toml");
    m << "[model]\nname = \"mix\"\ncoordinates = [\"x\", \"y\"]\n[model.parameters]\n"
         "k = 3.0\nx0 = 1000.0\n[model.define]\nr = \"sqrt((x - x0)^2 + y^2 + 1e-3)\"\n"
         "[model.energy]\nkinetic = \"0.5*(1 + 0.1*sin(y)^2)*x_d^2 + 0.5*y_d^2 + 0.01*cos(x)*x_d*y_d\"\n"
         "potential = \"k*(x - x0)^4/4 + 1e-7*(y - 3)^6 + 1e3*(r - 1)^2 + exp(-y^2)*(x - x0) + "
         "y*(x - x0)^3/7 + 1e-12*x^2\"\ndissipation = \"0.05*(x_d^2 + y_d^2)*(1 + r^2)\"\n"
         "[model.outputs]\nE = \"0.5*x_d^2 + 0.5*y_d^2 + k*(x - x0)^4/4\"\n";
    std::ofstream c(dir.path / "mix_case.toml");
    c << "model = \"mix.toml\"\n[initial]\nx = 1000.3\ny = 0.7\n[solver]\nt_end = 2.0\n"
         "[output]\ndt = 1e-2\n";
  }
  const auto r1 = pcsim_test::sh(pcsim_test::exe() + " run mix_case.toml --out a", dir.path);
  const auto r2 = pcsim_test::sh(pcsim_test::exe() + " run mix_case.toml --out b", dir.path);
  BOOST_TEST_REQUIRE(r1.status == 0, r1.out);
  BOOST_TEST_REQUIRE(r2.status == 0, r2.out);
  const std::string a = pcsim_test::read(dir.path / "a" / "timeseries.csv");
  const std::string b = pcsim_test::read(dir.path / "b" / "timeseries.csv");
  BOOST_TEST(a.size() > 1000u);
  BOOST_TEST((a == b), "the two processes' time series differ");
}

// Loads of one file give the same tape, whatever GiNaC did before (symbol serials, and so its
// order of sums and products, change from load to load; so may where it puts a number or a
// sign in a product: -(a - b)*c or (b - a)*c): every model file of models/ and a model that
// mixes offsets, definitions and functions, loaded 5 times each (3 under the sanitizers, where a
// spatial model's load costs seconds; the two Release builds of CI load 5).
BOOST_AUTO_TEST_CASE(every_load_of_a_file_gives_the_same_tape) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& entry : std::filesystem::directory_iterator(model_path(""))) {
    if (entry.path().extension() == ".toml") files.push_back({entry.path().filename().string(), pcsim_test::read(entry.path())});
  }
  files.push_back({"mix", "[model]\nname = \"mix\"\ncoordinates = [\"x\", \"y\"]\n"
                          "[model.parameters]\nk = 3.0\nx0 = 1000.0\n[model.define]\n"
                          "r = \"sqrt((x - x0)^2 + y^2 + 1e-3)\"\nw = \"(x0 - x)*r - 2*(y - x)*k\"\n"
                          "[model.energy]\nkinetic = \"0.5*(1 + w^2)*x_d^2 + 0.5*y_d^2\"\n"
                          "potential = \"k*(x - x0)^4/4 - (y - 3)^6*(x0 - x) + w*r - 3*(2 - y)*(x - 1)\"\n"});
  // A spatial bushing between two moving bodies, its markers turned about skew axes (issue 22,
  // BSH): with the markers' axes written inline, A = E1ᵀ E2 changed the tape from load to load.
  files.push_back({"bushing_skew", "[model]\nname = \"bushing_skew\"\n[model.body.a]\nkind = \"spatial\"\n"
                                   "mass = 1.0\ninertia = [0.1, 0.2, 0.25]\n"
                                   "markers = { p = { at = [0.1, 0.2, 0.3], axis = [1, 2, 3], angle = 0.7 } }\n"
                                   "[model.body.b]\nkind = \"spatial\"\nmass = 2.0\ninertia = [0.3, 0.2, 0.4]\n"
                                   "markers = { q = { at = [-0.2, 0.1, 0.05], axis = [-2, 1, 0.5], angle = -1.9 } }\n"
                                   "[model.force.mount]\ntype = \"bushing\"\nbody1 = \"a\"\nmarker1 = \"p\"\n"
                                   "body2 = \"b\"\nmarker2 = \"q\"\nstiffness = [1, 2, 3]\ndamping = [1, 1, 1]\n"
                                   "rotational_stiffness = [3, 5, 7]\nrotational_damping = [0.3, 0.5, 0.7]\n"});
  BOOST_TEST_REQUIRE(files.size() >= 8u);
  for (const auto& [name, text] : files) {
    std::string first;
    const int loads = pcsim_test::slow_build() ? 3 : 5;
    for (int k = 0; k < loads; ++k) {
      const auto d = load_model_text(text, name);
      const Tape& t = d->compiled().tape;
      std::ostringstream o;
      for (const auto& [slot, v] : t.literals) o << slot << "=" << text_of(v) << ";";
      Block prelude;
      prelude.code = t.prelude;
      o << listing(t, prelude);
      for (const Block& b : t.blocks) o << "|" << listing(t, b);
      if (k == 0) first = o.str();
      BOOST_TEST((o.str() == first), name << ": load " << k << " gives another tape");
    }
  }
}

// `pcsim expand` prints the same text in every process (issue 22's expand contract): the texts
// it derives with GiNaC (a drive's velocity, a marker's acceleration) are printed by
// detail::canonical_text, not by GiNaC, whose order of factors follows hash values seeded with
// the addresses of type names, which address-space randomization moves from run to run: the
// vibrating table's slot velocity printed `A*omega*cos(t*omega)` in some runs and
// `A*cos(t*omega)*omega` in others (4 different texts in 6 runs before the fix). Six fresh
// processes per model (three under the sanitizers, where a load costs seconds).
BOOST_AUTO_TEST_CASE(expanded_text_is_the_same_in_every_process) {
  pcsim_test::TempDir dir("evalorder_expand");
  const int processes = pcsim_test::slow_build() ? 3 : 6;
  for (const char* m : {"contact/table_ball_bodies.toml", "sieve_1995_bodies.toml"}) {
    std::string first;
    for (int k = 0; k < processes; ++k) {
      const auto r = pcsim_test::sh(pcsim_test::exe() + " expand '" + model_path(m).string() + "'", dir.path);
      BOOST_TEST_REQUIRE(r.status == 0, r.out);
      if (k == 0) first = r.out;
      BOOST_TEST((r.out == first), m << ": process " << k << " printed another text");
    }
  }
}

// canonical_text orders sums and products by their own texts: the same expression built from
// symbols made in either order (GiNaC orders by their serial numbers) prints the same, and the
// text reads back to the expression (pi included, printed as the language's `pi`).
BOOST_AUTO_TEST_CASE(canonical_text_does_not_depend_on_the_order_symbols_were_made) {
  // The symbols made in each of the six orders (GiNaC orders sums and products, and picks the
  // sign of a sum factor, by their serial numbers).
  auto build = [](int order) {
    std::map<std::string, GiNaC::symbol> s;
    std::vector<std::string> names{"A", "omega", "t"};
    for (int k = 0; k < order; ++k) std::next_permutation(names.begin(), names.end());
    for (const std::string& n : names) s.emplace(n, GiNaC::symbol(n));
    const GiNaC::ex w = s.at("omega"), A = s.at("A"), t = s.at("t");
    const GiNaC::ex e = A * GiNaC::sin(w * t + GiNaC::Pi / 3) * GiNaC::pow(w, 3) - GiNaC::numeric(3, 2) * GiNaC::sqrt(A + t) / w +
                        GiNaC::atan2(t, A) * (w - A) * (t + 1);
    return std::make_pair(e.diff(GiNaC::ex_to<GiNaC::symbol>(t)), s);
  };
  std::string first;
  for (int order = 0; order < 6; ++order) {
    const auto [e, syms] = build(order);
    const std::string c = detail::canonical_text(e);
    if (order == 0) {
      first = c;
      BOOST_TEST_MESSAGE(c);
    }
    BOOST_TEST(c == first, "symbols in order " << order);
    detail::ExpressionParser p;
    for (const auto& [n, sym] : syms) p.define(n, sym);
    const GiNaC::ex back = p.parse(detail::ExprText{"test", "canonical", c});
    BOOST_TEST((back - e).expand().is_zero(), "read back: " << back);
  }
}
