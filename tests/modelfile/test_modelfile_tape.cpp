// The evaluation tape computes what the symbolic expressions say: at random states, every
// result of every model file (M, h, Q, the constraint rows g, g0, γ, the position residuals Φ
// and the outputs) equals GiNaC's own numeric evaluation (17 digits) of the symbolic expression
// it was compiled from, and the tape's forward mode equals GiNaC's symbolic derivatives with
// respect to q, q̇ and t. A model that uses every allowed function covers every tape operation
// and its derivative; a 120-coordinate chain shows that size is not limited.
#define BOOST_TEST_MODULE modelfile_tape
#include <boost/test/unit_test.hpp>

#include <mutex>
#include <set>

#include "chain_model.hpp"
#include "modelfile/expression.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile/symbolic.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;
using GiNaC::ex;

namespace {

// A model that uses every function of the contract, t, pi, a term linear in the velocities,
// a Rayleigh function, applied forces, both kinds of constraint and outputs with R and q̈.
// M = [[2 + sin(a)^2, 0.1 atan(a) + 0.01 t], [., 3 + cosh(b)/2]] is positive definite.
const char* kFunctionsModel = R"TOML(
[model]
name = "functions"
coordinates = ["a", "b", "c"]
[model.parameters]
k = 1.5
w = { value = 2.0, min = 0.0 }
[model.define]
s2 = "sin(a)^2"
[model.energy]
kinetic = "0.5*(2 + s2)*a_d^2 + 0.5*(3 + cosh(b)/2)*b_d^2 + (0.1*atan(a) + 0.01*t)*a_d*b_d + 0.5*k*c_d^2 + exp(-b^2)*cos(w*t)*a_d + sinh(b/3)*c_d"
potential = "log(2 + a^2) + a*log(2 + b^2) + sqrt(1 + b^2) + pow(2, a*b/10) + pow(1 + a^2, b/3) + tanh(a) + k*abs(c - 3) + tan(a/5)*t + 0.01*a^6 + 0.1*min(a, b)^2"
dissipation = "0.5*k*(a_d^2 + b_d^2)*(1 + a^2/10) + 0.1*c_d^4"
[model.forces]
a = "max(a, b) - min(a_d, b_d)"
c = "atan2(b, 1 + a^2) + pi/10"
[[model.constraint]]
name = "curve"
holonomic = "asin(a/3) + acos(b/4) + atan2(c, 2 + a^2) + tan(a/5) - 1 + 0.1*sin(w*t)"
[[model.constraint]]
name = "slide"
velocity = { a = "cos(b)", c = "1 + a^2*t" }
velocity0 = "exp(a/5)*sin(t)"
[[model.constraint]]
name = "fixed"
holonomic = "c - b*a"
from_initial = true
[model.outputs]
power = "R_a*a_d + R_b*b_d + R_c*c_d"
accel = "a_dd^2 + min(b_dd, c_dd) + abs(R_c) + b_d^7"
)TOML";

struct Symbolic {
  detail::ModelSource source;
  detail::SymbolicModel model;
};

// The model's expressions with the definitions substituted (the derivation keeps them as
// symbols; GiNaC's evaluation and differentiation below need the coordinates alone).
void inline_definitions(detail::SymbolicModel& m) {
  auto in = [&](ex& e) { e = detail::inline_definitions(m, e); };
  for (auto& row : m.M)
    for (ex& e : row) in(e);
  for (ex& e : m.h) in(e);
  for (ex& e : m.Q) in(e);
  in(m.T);
  in(m.V);
  in(m.F);
  for (auto& c : m.constraints) {
    in(c.phi);
    for (ex& e : c.g) in(e);
    in(c.g0);
    in(c.gamma);
  }
  for (ex& e : m.outputs) in(e);
  if (m.period) in(*m.period);
}

Symbolic derive_file(const std::filesystem::path& file) {
  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  Symbolic s{detail::load_model_source(file), {}};
  s.model = detail::derive(s.source);
  inline_definitions(s.model);
  return s;
}

Symbolic derive_text(const std::string& text) {
  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  const toml::table doc = toml::parse(text);
  Symbolic s{detail::read_model_source(*doc["model"].as_table(), "functions.toml", "model"), {}};
  s.model = detail::derive(s.source);
  inline_definitions(s.model);
  return s;
}

double value(const ex& e, const GiNaC::exmap& at) {
  const ex v = e.subs(at).evalf();
  BOOST_REQUIRE_MESSAGE(GiNaC::is_a<GiNaC::numeric>(v), "not a number: " << v);
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

// A test point: the state and the parameter values, and the GiNaC substitution for them.
struct Point {
  double t;
  Eigen::VectorXd q, qd, qdd, R;
  std::map<std::string, double> parameters;
  Eigen::VectorXd q0;
  GiNaC::exmap at;
};

// States: q, q̇ of order `scale` around `centre`; qdd and R of order 1. The from_initial
// constants are Φ(q0, 0) at a second random state q0 (as instantiate() computes them).
Point random_point(const Symbolic& s, std::mt19937& rng, double centre, double scale) {
  const auto& m = s.model;
  const int n = m.n;
  Point p;
  p.t = 0.3 + 0.2 * uniform(rng);
  p.q.resize(n);
  p.qd.resize(n);
  p.qdd.resize(n);
  p.R.resize(n);
  p.q0.resize(n);
  for (int i = 0; i < n; ++i) {
    p.q[i] = centre + scale * uniform(rng);
    p.q0[i] = centre + scale * uniform(rng);
    p.qd[i] = uniform(rng);
    p.qdd[i] = uniform(rng);
    p.R[i] = uniform(rng);
  }
  for (std::size_t i = 0; i < s.source.parameters.size(); ++i) {
    // Perturbed defaults (a zero default would hide the terms it multiplies).
    const auto& spec = s.source.parameters[i];
    double v = spec.value == 0.0 ? 0.05 * (1 + uniform(rng)) : spec.value * (1 + 0.1 * uniform(rng));
    if (!spec.admits(v)) v = spec.value;
    p.parameters[spec.name] = v;
    p.at[m.parameters[i]] = v;
  }
  GiNaC::exmap at0 = p.at;
  p.at[m.t] = p.t;
  at0[m.t] = 0.0;
  for (int i = 0; i < n; ++i) {
    p.at[m.q[i]] = p.q[i];
    p.at[m.qd[i]] = p.qd[i];
    p.at[m.qdd[i]] = p.qdd[i];
    p.at[m.R[i]] = p.R[i];
    at0[m.q[i]] = p.q0[i];
  }
  for (const auto& c : m.constraints) {
    if (c.hidden < 0) continue;
    at0[m.hidden[c.hidden]] = 0.0;
    p.at[m.hidden[c.hidden]] = value(c.phi, at0);  // Φ(q0, 0) − 0
  }
  return p;
}

// Everything a model evaluates, from the tape and from GiNaC, compared block by block.
void compare_values(const Symbolic& s, const ExpressionModel& model, const Point& p,
                    double tol) {
  const auto& m = s.model;
  const int n = m.n;
  const int nc = static_cast<int>(m.constraints.size());
  std::vector<int> all(nc);
  for (int i = 0; i < nc; ++i) all[i] = i;
  const Evaluation e = evaluate(model, all, p.t, p.q, p.qd);
  Evaluation g;
  g.M.resize(n, n);
  g.h.resize(n);
  g.Q.resize(n);
  g.g.resize(nc, n);
  g.g0.resize(nc);
  g.gamma.resize(nc);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) g.M(i, j) = value(m.M[i][j], p.at);
    g.h[i] = value(m.h[i], p.at);
    g.Q[i] = value(m.Q[i], p.at);
  }
  Eigen::VectorXd phi_tape(nc), phi_ginac(nc);
  for (int r = 0; r < nc; ++r) {
    for (int k = 0; k < n; ++k) g.g(r, k) = value(m.constraints[r].g[k], p.at);
    g.g0[r] = value(m.constraints[r].g0, p.at);
    g.gamma[r] = value(m.constraints[r].gamma, p.at);
    const bool hol = m.constraints[r].holonomic;
    phi_tape[r] = hol ? model.position_residual(r, p.t, p.q) : 0.0;
    phi_ginac[r] = hol ? value(m.constraints[r].phi, p.at) : 0.0;
    BOOST_TEST(hol == !std::isnan(model.position_residual(r, p.t, p.q)));
  }
  Eigen::VectorXd out_tape, out_ginac(m.outputs.size());
  model.derived(p.t, p.q, p.qd, p.qdd, p.R, out_tape);
  for (std::size_t i = 0; i < m.outputs.size(); ++i) out_ginac[i] = value(m.outputs[i], p.at);
  BOOST_TEST(rel_diff(e.M, g.M, 1.0) < tol);
  BOOST_TEST(rel_diff(e.h, g.h, 1.0) < tol);
  BOOST_TEST(rel_diff(e.Q, g.Q, 1.0) < tol);
  BOOST_TEST(rel_diff(e.g, g.g, 1.0) < tol);
  BOOST_TEST(rel_diff(e.g0, g.g0, 1.0) < tol);
  BOOST_TEST(rel_diff(e.gamma, g.gamma, 1.0) < tol);
  BOOST_TEST(rel_diff(phi_tape, phi_ginac, 1.0) < tol);
  BOOST_TEST(rel_diff(out_tape, out_ginac, 1.0) < tol);
}

// The directional derivative of e along column j of V ((2n+1) x k: δq, δq̇, δt) by GiNaC.
double directional(const Symbolic& s, const ex& e, const Eigen::MatrixXd& V, int j,
                   const GiNaC::exmap& at) {
  const auto& m = s.model;
  const int n = m.n;
  ex d = e.diff(GiNaC::ex_to<GiNaC::symbol>(m.t)) * V(2 * n, j);
  for (int l = 0; l < n; ++l) {
    d += e.diff(GiNaC::ex_to<GiNaC::symbol>(m.q[l])) * V(l, j);
    d += e.diff(GiNaC::ex_to<GiNaC::symbol>(m.qd[l])) * V(n + l, j);
  }
  return value(d, at);
}

void compare_tangents(const Symbolic& s, const ExpressionModel& model, const Point& p,
                      std::mt19937& rng, double tol) {
  const auto& m = s.model;
  const int n = m.n, k = 3;
  const int nc = static_cast<int>(m.constraints.size());
  Eigen::MatrixXd V(2 * n + 1, k);
  for (int i = 0; i < V.rows(); ++i)
    for (int j = 0; j < k; ++j) V(i, j) = uniform(rng);
  Eigen::MatrixXd M, dh, dQ, g, dg0, dgamma;
  Eigen::VectorXd h, Q, g0, gamma;
  std::vector<Eigen::MatrixXd> dM, dg;
  std::vector<int> all(nc);
  for (int i = 0; i < nc; ++i) all[i] = i;
  model.kinetic_terms_tangent(p.t, p.q, p.qd, V, M, h, dM, dh);
  model.forces_tangent(p.t, p.q, p.qd, V, Q, dQ);
  model.constraint_rows_tangent(all, p.t, p.q, p.qd, V, g, g0, gamma, dg, dg0, dgamma);
  // The values of the tangent calls equal the plain calls exactly (the same tape).
  const Evaluation e = evaluate(model, all, p.t, p.q, p.qd);
  BOOST_TEST(rel_diff(M, e.M) == 0.0);
  BOOST_TEST(rel_diff(h, e.h) == 0.0);
  BOOST_TEST(rel_diff(Q, e.Q) == 0.0);
  BOOST_TEST(rel_diff(g, e.g) == 0.0);
  BOOST_TEST(rel_diff(gamma, e.gamma) == 0.0);
  for (int j = 0; j < k; ++j) {
    Eigen::MatrixXd gM(n, n), gg(nc, n);
    Eigen::VectorXd gh(n), gQ(n), gg0(nc), ggamma(nc);
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) gM(a, b) = directional(s, m.M[a][b], V, j, p.at);
      gh[a] = directional(s, m.h[a], V, j, p.at);
      gQ[a] = directional(s, m.Q[a], V, j, p.at);
    }
    for (int r = 0; r < nc; ++r) {
      for (int b = 0; b < n; ++b) gg(r, b) = directional(s, m.constraints[r].g[b], V, j, p.at);
      gg0[r] = directional(s, m.constraints[r].g0, V, j, p.at);
      ggamma[r] = directional(s, m.constraints[r].gamma, V, j, p.at);
    }
    BOOST_TEST_CONTEXT("direction " << j) {
      BOOST_TEST(rel_diff(dM[j], gM, 1.0) < tol);
      BOOST_TEST(rel_diff(dh.col(j), gh, 1.0) < tol);
      BOOST_TEST(rel_diff(dQ.col(j), gQ, 1.0) < tol);
      BOOST_TEST(rel_diff(dg[j], gg, 1.0) < tol);
      BOOST_TEST(rel_diff(dg0.col(j), gg0, 1.0) < tol);
      BOOST_TEST(rel_diff(dgamma.col(j), ggamma, 1.0) < tol);
    }
  }
}

std::shared_ptr<const ExpressionModel> instantiate(const ModelDescription& d, const Point& p) {
  auto m = std::dynamic_pointer_cast<const ExpressionModel>(d.instantiate(p.parameters, p.q0, 0.0));
  BOOST_REQUIRE(m);
  return m;
}

struct FileCase {
  const char* file;
  double centre, scale;  // where the random coordinates lie
};

const std::vector<FileCase>& files() {
  static const std::vector<FileCase> f = {
      {"pendulum.toml", 0.0, 1.0},        {"rolling_disk.toml", 0.0, 1.0},
      {"slider_crank.toml", 0.0, 1.0},    {"double_pendulum.toml", 0.5, 0.4},
      {"double_pendulum_minimal.toml", 0.0, 1.0}, {"knife_edge.toml", 0.0, 1.0},
      {"sieve_1995.toml", 0.1, 0.3},      {"pendulum_chain_30.toml", 0.0, 1.0},
  };
  return f;
}

}  // namespace

// Tolerance 1e-12 relative to the block's largest entry (or 1): the tape evaluates in double the
// same expression GiNaC evaluates in 17 digits; the difference is the tape's rounding, a few
// ulps of the largest intermediate term, and these models have no cancellation worse than 1e3.
BOOST_AUTO_TEST_CASE(tape_equals_ginac_evaluation_for_every_model_file) {
  std::mt19937 rng(11);
  for (const FileCase& f : files()) {
    BOOST_TEST_CONTEXT(f.file) {
      const Symbolic s = derive_file(model_path(f.file));
      const auto d = load_model_file(model_path(f.file));
      for (int trial = 0; trial < 3; ++trial) {
        const Point p = random_point(s, rng, f.centre, f.scale);
        std::lock_guard<std::mutex> lock(detail::ginac_mutex());
        compare_values(s, *instantiate(*d, p), p, 1e-12);
      }
    }
  }
}

// Tolerance 1e-12 as above: forward mode applies the chain rule to the same operations.
BOOST_AUTO_TEST_CASE(tangents_equal_symbolic_derivatives_for_every_model_file) {
  std::mt19937 rng(12);
  for (const FileCase& f : files()) {
    if (std::string(f.file) == "pendulum_chain_30.toml") continue;  // the 120-link case below
    BOOST_TEST_CONTEXT(f.file) {
      const Symbolic s = derive_file(model_path(f.file));
      const auto d = load_model_file(model_path(f.file));
      const Point p = random_point(s, rng, f.centre, f.scale);
      std::lock_guard<std::mutex> lock(detail::ginac_mutex());
      compare_tangents(s, *instantiate(*d, p), p, rng, 1e-12);
    }
  }
}

BOOST_AUTO_TEST_CASE(every_function_and_its_derivative_on_the_tape) {
  std::mt19937 rng(13);
  const Symbolic s = derive_text(kFunctionsModel);
  const toml::table doc = toml::parse(kFunctionsModel);
  const auto d = parse_model_table(*doc["model"].as_table(), "functions.toml");
  // Every operation of the tape occurs (so every case of run and run_tangent is exercised).
  std::set<Op> ops;
  for (const Block& b : d->compiled().tape.blocks)
    for (const Instr& in : b.code) ops.insert(in.op);
  for (Op op : {Op::add, Op::sub, Op::mul, Op::div, Op::neg, Op::recip, Op::sqr, Op::powi,
                Op::pow, Op::sqrt, Op::tan, Op::asin, Op::acos, Op::atan, Op::atan2, Op::sinh,
                Op::cosh, Op::exp, Op::log, Op::abs, Op::step, Op::min, Op::max,
                Op::sincos, Op::madd, Op::msub, Op::nmadd}) {
    BOOST_TEST_CONTEXT(to_string(op)) { BOOST_TEST(ops.count(op) == 1u); }
  }
  for (int trial = 0; trial < 5; ++trial) {
    // a, b, c in [-0.8, 0.8]: inside the domains of asin(a/3), acos(b/4), log(2 + a^2).
    const Point p = random_point(s, rng, 0.0, 0.8);
    std::lock_guard<std::mutex> lock(detail::ginac_mutex());
    const auto m = instantiate(*d, p);
    compare_values(s, *m, p, 1e-12);
    compare_tangents(s, *m, p, rng, 1e-12);
  }
}

// Models are not limited in size (the AD models of the engine stop at 16 coordinates).
BOOST_AUTO_TEST_CASE(a_chain_of_40_links_with_120_coordinates_evaluates_like_its_symbols) {
  std::mt19937 rng(14);
  const std::string text = pendulum_chain_toml(40);
  const Symbolic s = derive_text(text);
  const toml::table doc = toml::parse(text);
  const auto d = parse_model_table(*doc["model"].as_table(), "chain40.toml");
  BOOST_TEST(d->n() == 120);
  BOOST_TEST(d->constraints().size() == 80u);
  const Point p = random_point(s, rng, 0.0, 1.0);
  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  const auto m = instantiate(*d, p);
  compare_values(s, *m, p, 1e-12);
}

// Fusing a mul into the add or sub that is its only use changes nothing but the instruction
// count: the fused operation rounds the product and the sum separately, as before (the project
// compiles without floating-point contraction). Values and tangents are bit-identical, and a
// product that is also a result, or used twice, stays.
BOOST_AUTO_TEST_CASE(multiply_add_fusion_keeps_results_bit_identical) {
  // slots 0..3 inputs; 4 = 0*1, 5 = 4 + 2, 6 = 3 - (2*3), 7 = 2*3, 8 = (0*2) - 1, 9 = 0*2 twice used
  std::vector<Instr> code = {
      {Op::mul, 4, 0, 1}, {Op::add, 5, 2, 4},  {Op::mul, 7, 2, 3},  {Op::sub, 6, 3, 7},
      {Op::mul, 9, 0, 2}, {Op::sub, 8, 9, 1},  {Op::mul, 10, 1, 3}, {Op::add, 11, 10, 10},
      {Op::mul, 12, 0, 3}, {Op::add, 13, 12, 0},
  };
  std::vector<Instr> fused = code;
  fuse_multiply_add(fused, {5, 6, 8, 11, 13, 12});  // 12 is a result: its mul stays
  std::set<Op> ops;
  for (const Instr& in : fused) ops.insert(in.op);
  BOOST_TEST(ops.count(Op::madd) == 1u);
  BOOST_TEST(ops.count(Op::msub) == 1u);
  BOOST_TEST(ops.count(Op::nmadd) == 1u);
  BOOST_TEST(fused.size() == code.size() - 3);  // 10 (used twice) and 12 (a result) stay
  std::mt19937 rng(15);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<double> v(14, 0.0), w(14, 0.0), dv(14 * 2, 0.0), dw(14 * 2, 0.0);
    for (int i = 0; i < 4; ++i) {
      v[i] = w[i] = 1e3 * uniform(rng);
      for (int j = 0; j < 2; ++j) dv[2 * i + j] = dw[2 * i + j] = uniform(rng);
    }
    run(code, v.data());
    run(fused, w.data());
    for (std::uint32_t r : {5u, 6u, 8u, 11u, 13u, 12u}) BOOST_TEST(v[r] == w[r]);
    run_tangent(code, v.data(), dv.data(), 2);
    run_tangent(fused, w.data(), dw.data(), 2);
    for (std::uint32_t r : {5u, 6u, 8u, 11u, 13u, 12u}) {
      for (int j = 0; j < 2; ++j) BOOST_TEST(std::abs(dv[2 * r + j] - dw[2 * r + j]) <= 1e-12 * (1 + std::abs(dv[2 * r + j])));
    }
  }
}
