// Chained definitions derive in time linear in their number (issue 19: 30 chained
// d_k = sin(d_{k-1}) + cos(d_{k-1}), or 8 rational d*d/(d*d+1), took exponential time), and
// their values and derivatives are right: checked against a direct evaluation of the chain in
// long double with forward-mode derivatives (dual numbers) written here. A model whose
// derivatives would grow without bound is refused by the derivation budget with an input
// error naming the file and the key. Load times are printed, not asserted.
#define BOOST_TEST_MODULE modelfile_derivation
#include <boost/test/unit_test.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

// A value and its derivative with respect to x.
struct Dual {
  long double v, d;
};

struct Chain {
  const char* name;
  const char* d0;      // the first definition, in x
  long double offset;  // d0 = x + offset
  const char* step;    // d_k in terms of "d" (d_{k-1})
  std::function<Dual(Dual)> f;  // the same step on duals
};

// The model: V = d_N, T = (1/2)(3 + c d_N) x_d^2 (c = 0 or 1: the chain in M and h as well),
// an output with d_N.
std::string chain_model(const Chain& c, int N, bool in_kinetic) {
  std::ostringstream f;
  f << "[model]\nname = \"chain\"\ncoordinates = [\"x\"]\n[model.define]\nd0 = \"" << c.d0 << "\"\n";
  for (int k = 1; k <= N; ++k) {
    std::string s = c.step, prev = "d" + std::to_string(k - 1);
    std::string out;
    for (char ch : s) out += ch == 'd' ? prev : std::string(1, ch);
    f << "d" << k << " = \"" << out << "\"\n";
  }
  f << "[model.energy]\nkinetic = \"0.5*(3" << (in_kinetic ? " + d" + std::to_string(N) : "")
    << ")*x_d^2\"\npotential = \"d" << N << "\"\n[model.outputs]\ndN = \"d" << N << "\"\n";
  return f.str();
}

const std::vector<Chain>& chains() {
  static const std::vector<Chain> c = {
      {"sin+cos", "x", 0, "sin(d) + cos(d)",
       [](Dual a) { return Dual{std::sin(a.v) + std::cos(a.v), (std::cos(a.v) - std::sin(a.v)) * a.d}; }},
      {"rational", "x + 1", 1, "d*d/(d*d + 1)",
       [](Dual a) {
         const long double s = a.v * a.v + 1;
         return Dual{a.v * a.v / s, 2 * a.v / (s * s) * a.d};
       }},
      {"rational, growing", "x + 1", 1, "1 + d*d/(d*d/4 + 1)",
       [](Dual a) {
         const long double s = a.v * a.v / 4 + 1;
         return Dual{1 + a.v * a.v / s, 2 * a.v / (s * s) * a.d};
       }},
  };
  return c;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// 30 chained sin+cos definitions, 8 and 30 rational ones (and 150 of each), in V and in T:
// they load in well under a second each, and Q = -V'(x), M = 3 + d_N, h = (1/2) d_N' x_d^2
// and the output d_N equal the direct evaluation of the chain.
BOOST_AUTO_TEST_CASE(chained_definitions_derive_fast_and_evaluate_right) {
  for (const Chain& c : chains()) {
    for (int N : {8, 30, 150}) {
      for (bool in_kinetic : {false, true}) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto d = load_model_text(chain_model(c, N, in_kinetic), "chain.toml");
        const double load = seconds_since(t0);
        std::printf("%-18s N = %3d %-10s load %.4f s, %zu tape instructions\n", c.name, N,
                    in_kinetic ? "(V and T)" : "(V)", load,
                    d->compiled().tape.instruction_count());
        const auto m = d->instantiate({});
        for (double x : {-0.7, 0.3, 1.9}) {
          Dual a{static_cast<long double>(x) + c.offset, 1.0L};
          for (int k = 1; k <= N; ++k) a = c.f(a);
          Eigen::VectorXd q(1), qd(1), Q(1), h(1), out(1), zero = Eigen::VectorXd::Zero(1);
          Eigen::MatrixXd M(1, 1);
          q << x;
          qd << 0.8;
          m->forces(0.0, q, qd, Q);
          m->kinetic_terms(0.0, q, qd, M, h);
          m->derived(0.0, q, qd, zero, zero, out);
          // The chain's condition grows with N (each step multiplies errors by |f'| up to 1.x);
          // 1e-12 absolute-or-relative is far above the double evaluation's error here and far
          // below any wrong derivative.
          auto close = [](double got, long double want) {
            return std::abs(got - static_cast<double>(want)) <=
                   1e-12 * std::max(1.0, std::abs(static_cast<double>(want)));
          };
          BOOST_TEST(close(out[0], a.v), c.name << " N=" << N << " x=" << x << ": d_N " << out[0]
                                                << " vs " << static_cast<double>(a.v));
          BOOST_TEST(close(Q[0], -a.d), c.name << " N=" << N << " x=" << x << ": Q " << Q[0]
                                               << " vs " << static_cast<double>(-a.d));
          BOOST_TEST(close(M(0, 0), 3 + (in_kinetic ? a.v : 0)));
          BOOST_TEST(close(h[0], in_kinetic ? 0.5L * a.d * 0.8L * 0.8L : 0.0L),
                     c.name << " N=" << N << ": h " << h[0]);
        }
      }
    }
  }
}

// A derivative that would grow past the budget is an input error naming the file, the key
// and the budget, and it comes quickly: the derivative of a product of 1,500 factors of x has
// 1,500 terms of 1,500 factors each (2.25 million operations; chained definitions cannot
// grow so, each being one node).
BOOST_AUTO_TEST_CASE(a_derivation_past_the_budget_is_an_input_error) {
  std::ostringstream f;
  f << "[model]\nname = \"huge\"\ncoordinates = [\"x\"]\n[model.energy]\n"
       "kinetic = \"0.5*x_d^2\"\npotential = \"";
  for (int k = 0; k < 1500; ++k) f << (k ? "*" : "") << "sin(x+" << k << ")";
  f << "\"\n";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = input_error_of([&] { load_model_text(f.str(), "huge.toml"); });
  std::printf("product of 1500 factors: refused after %.2f s\n", seconds_since(t0));
  BOOST_TEST(contains_all(msg, {"huge.toml", "model.energy.potential", "derivation budget",
                                "2000000"}),
             msg);
}

// Definitions nested deeper than the limit (1000 levels of expression, counted through the
// definitions) are an input error naming the file, the definition's key and the limit, not a
// stack overflow: 1,500 chained d_k = sin(d_{k-1}) + cos(d_{k-1}) (within the limit of 2000
// definitions) stop at d_500; 10,000 are refused by that count before any is parsed.
BOOST_AUTO_TEST_CASE(definitions_nested_past_the_depth_limit_are_an_input_error) {
  const Chain& c = chains()[0];
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = input_error_of([&] { load_model_text(chain_model(c, 1500, true), "deep.toml"); });
  std::printf("1500 chained definitions: refused after %.2f s\n", seconds_since(t0));
  BOOST_TEST(contains_all(msg, {"deep.toml", "model.define.d500", "limit of 1000"}), msg);
  const std::string many = input_error_of([&] { load_model_text(chain_model(c, 10000, true), "deep.toml"); });
  BOOST_TEST(contains_all(many, {"deep.toml", "model.define", "at most 2000 definitions"}), many);
  // 450 levels (depth 901) are within it.
  BOOST_TEST(load_model_text(chain_model(c, 450, true), "deep.toml")->n() == 1);
}
