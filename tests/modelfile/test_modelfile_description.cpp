// The ModelDescription API: what a model file declares comes back in file order (parameters
// with units and ranges, constraints with their attributes, outputs as columns); inline
// [model] tables name their keys; definitions may come in any order; constraints added from
// the command line and from_initial constants work; descriptions are immutable and
// instantiated models are independent, also when used alternately and from several threads.
#define BOOST_TEST_MODULE modelfile_description
#include <boost/test/unit_test.hpp>

#include <thread>

#include "mech/simulation.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

std::shared_ptr<const ModelDescription> from_text(const std::string& text,
                                                  const std::string& prefix = "model") {
  const toml::table doc = toml::parse(text);
  const toml::table* t = doc.get_as<toml::table>("model");
  BOOST_REQUIRE(t);
  return parse_model_table(*t, "case.toml", prefix);
}

// A cart (x) with a pendulum (angle a) whose length and a time-dependent support motion make
// every evaluation path non-trivial; outputs are declared in a non-alphabetical order.
const char* kCart = R"TOML(
[model]
name = "cart"
coordinates = ["x", "a"]
period = "2*pi/w"
[model.parameters]
M = { value = 2.0, unit = "kg", meaning = "cart mass", positive = true }
m = { value = 0.5, unit = "kg", meaning = "bob mass", min = 0.0, min_exclusive = true }
l = { value = 0.7, unit = "m", max = 2.0 }
w = 3.0
[model.define]
xb = "x + l*sin(a)"       # uses vx before its definition below: the order is resolved
vx = "x_d + l*cos(a)*a_d"
[model.energy]
kinetic = "0.5*M*x_d^2 + 0.5*m*(vx^2 + (l*sin(a)*a_d)^2)"
potential = "-m*9.81*l*cos(a) + 0.5*x^2*(1 + 0.1*sin(w*t))"
[[model.constraint]]
name = "hold"
holonomic = "x - 0.1*sin(w*t)"
active = false
[model.outputs]
zz = "xb"
aa = "R_x"
)TOML";

}  // namespace

BOOST_AUTO_TEST_CASE(declarations_come_back_in_file_order) {
  const auto d = from_text(kCart);
  BOOST_TEST(d->name() == "cart");
  BOOST_TEST(d->source() == "case.toml");
  BOOST_TEST(d->coordinates() == (std::vector<std::string>{"x", "a"}));
  BOOST_REQUIRE(d->parameters().size() == 4u);
  BOOST_TEST(d->parameters()[0].name == "M");
  BOOST_TEST(d->parameters()[3].name == "w");
  const ParameterSpec& M = d->parameters()[0];
  BOOST_TEST(M.unit == "kg");
  BOOST_TEST(M.meaning == "cart mass");
  BOOST_TEST(M.range_text() == "a number > 0");
  BOOST_TEST(d->parameters()[1].range_text() == "a number > 0");
  BOOST_TEST(d->parameters()[2].range_text() == "a number <= 2");
  BOOST_TEST(d->parameters()[3].range_text() == "a finite number");
  BOOST_TEST(d->outputs().size() == 2u);
  BOOST_TEST(d->outputs()[0].name == "zz");
  BOOST_TEST(d->outputs()[1].expression == "R_x");
  BOOST_TEST(d->constraints()[0].holonomic == "x - 0.1*sin(w*t)");
  BOOST_TEST(!d->constraints()[0].active_by_default);
  BOOST_TEST(d->default_active_constraints().empty());
  BOOST_TEST(d->period_expression().value() == "2*pi/w");
  BOOST_TEST(std::abs(d->period() - 2 * M_PI / 3) < 1e-15);
  BOOST_TEST(d->slow_coordinates().empty());
  const auto model = d->instantiate({{"l", 0.5}});
  BOOST_TEST(model->derived_names() == (std::vector<std::string>{"zz", "aa"}));
  BOOST_TEST(model->constraints()[0].constant_row);   // g = [1, 0]
  Eigen::VectorXd q(2), qd(2), out;
  q << 0.2, 0.3;
  qd << 0.1, -0.4;
  model->derived(0.0, q, qd, Eigen::VectorXd::Zero(2), Eigen::Vector2d(7.0, 0.0), out);
  BOOST_TEST(std::abs(out[0] - (0.2 + 0.5 * std::sin(0.3))) < 1e-15);
  BOOST_TEST(out[1] == 7.0);
}

BOOST_AUTO_TEST_CASE(inline_tables_name_their_keys_with_the_prefix) {
  std::string text = kCart;
  text.replace(text.find("\"xb\""), 4, "\"xb + q\"");
  const std::string msg = input_error_of([&] { from_text(text, "model"); });
  BOOST_TEST(contains_all(msg, {"case.toml: key 'model.outputs.zz'", "unknown name 'q'"}));
  const std::string msg2 = input_error_of([&] { from_text(text, "cases.cart.model"); });
  BOOST_TEST(contains_all(msg2, {"key 'cases.cart.model.outputs.zz'"}));
}

BOOST_AUTO_TEST_CASE(numbers_are_expressions_and_terms_may_be_absent) {
  const auto d = from_text(R"TOML(
[model]
coordinates = ["s", "phi"]
[model.energy]
kinetic = "0.5*(s_d^2 + phi_d^2)"
potential = 0
[[model.constraint]]
name = "roll"
velocity = { s = 1, phi = -0.25 }
velocity0 = 0.5
)TOML");
  BOOST_TEST(d->name() == "case");  // the file stem
  const auto m = d->instantiate({});
  Eigen::MatrixXd g(1, 2);
  Eigen::VectorXd g0(1), gamma(1), Q(2);
  m->constraint_rows({0}, 0.0, Eigen::Vector2d(1, 2), Eigen::Vector2d(3, 4), g, g0, gamma);
  BOOST_TEST(g(0, 0) == 1.0);
  BOOST_TEST(g(0, 1) == -0.25);
  BOOST_TEST(g0[0] == 0.5);
  BOOST_TEST(gamma[0] == 0.0);
  m->forces(0.0, Eigen::Vector2d(1, 2), Eigen::Vector2d(3, 4), Q);
  BOOST_TEST(Q.norm() == 0.0);
  BOOST_TEST(std::isnan(d->period()));
}

// from_initial: Φ(q, t) − Φ(q0, t0); the constant follows q0 and t0 of each instantiation.
BOOST_AUTO_TEST_CASE(from_initial_constraints_are_fixed_at_the_initial_state) {
  std::string text = kCart;
  text.replace(text.find("holonomic = \"x - 0.1*sin(w*t)\""), 30,
               "holonomic = \"x + l*a + 0.1*sin(w*t)\"\nfrom_initial = true");
  const auto d = from_text(text);
  BOOST_TEST(d->constraints()[0].from_initial);
  const Eigen::Vector2d q0(0.3, -0.2);
  for (double t0 : {0.0, 0.4}) {
    const auto m = d->instantiate({}, q0, t0);
    BOOST_TEST(std::abs(m->position_residual(0, t0, q0)) < 1e-16);
    const Eigen::Vector2d q1(0.5, -0.2);
    BOOST_TEST(std::abs(m->position_residual(0, t0, q1) - 0.2) < 1e-15);
  }
}

BOOST_AUTO_TEST_CASE(added_constraints_become_part_of_a_new_description) {
  const auto d = load_model_file(model_path("sieve_1995.toml"));
  ExtraConstraint hold;
  hold.name = "hold_s";
  hold.holonomic = "s - 0.42";
  ExtraConstraint keep;
  keep.name = "keep_s";
  keep.holonomic = "s";
  keep.from_initial = true;
  const auto d2 = d->with_constraints({hold, keep});
  BOOST_TEST(d->constraints().size() == 5u);  // the original is unchanged
  BOOST_REQUIRE(d2->constraints().size() == 7u);
  BOOST_TEST(d2->constraints()[5].name == "hold_s");
  BOOST_TEST(d2->constraints()[5].added);
  BOOST_TEST(d2->constraints()[5].active_by_default);
  BOOST_TEST(d2->constraints()[6].from_initial);
  BOOST_TEST(d2->default_active_constraints() ==
             (std::vector<std::string>{"contact", "rolling", "hold_s", "keep_s"}));
  Eigen::VectorXd q0(6);
  q0 << 0, 0, 0, 0.4, 0.15, 0;
  const auto m = d2->instantiate({}, q0, 0.0);
  BOOST_TEST(std::abs(m->position_residual(5, 0.0, q0) + 0.02) < 1e-15);
  BOOST_TEST(std::abs(m->position_residual(6, 0.0, q0)) < 1e-16);
  // With the roller held, the reactions hold it: R_s carries the holding force too.
  const mech::ReactionResult r = mech::reactions(*m, {"contact", "rolling", "keep_s"}, 0.0, q0,
                                                 Eigen::VectorXd::Zero(6));
  BOOST_REQUIRE(r.issue == mech::ModelIssue::none);
  BOOST_TEST(std::abs(r.qdd[3]) < 1e-12);
}

// Two models from one description with different parameters, evaluated alternately in one
// thread (which shares one scratch array between them) and from two threads at once, give
// exactly what each gives alone.
BOOST_AUTO_TEST_CASE(instantiated_models_are_independent_and_thread_safe) {
  const auto d = from_text(kCart);
  const auto a = d->instantiate({{"l", 0.5}});
  const auto b = d->instantiate({{"l", 1.5}, {"m", 2.0}});
  const auto* ea = dynamic_cast<const ExpressionModel*>(a.get());
  const auto* eb = dynamic_cast<const ExpressionModel*>(b.get());
  BOOST_REQUIRE(ea);
  BOOST_REQUIRE(eb);
  std::mt19937 rng(9);
  std::vector<double> t(50);
  std::vector<Eigen::VectorXd> q(50), qd(50);
  for (int i = 0; i < 50; ++i) {
    t[i] = uniform(rng);
    q[i] = Eigen::Vector2d(uniform(rng), uniform(rng));
    qd[i] = Eigen::Vector2d(uniform(rng), uniform(rng));
  }
  auto all = [&](const ExpressionModel& m) {
    std::vector<Evaluation> out;
    for (int i = 0; i < 50; ++i) out.push_back(evaluate(m, {0}, t[i], q[i], qd[i]));
    return out;
  };
  const auto ref_a = all(*ea), ref_b = all(*eb);
  BOOST_TEST(rel_diff(ref_a[0].M, ref_b[0].M) > 0.1);  // they do differ
  // Alternating in one thread.
  for (int i = 0; i < 50; ++i) {
    const Evaluation x = evaluate(*ea, {0}, t[i], q[i], qd[i]);
    const Evaluation y = evaluate(*eb, {0}, t[i], q[i], qd[i]);
    BOOST_TEST(rel_diff(x.M, ref_a[i].M) == 0.0);
    BOOST_TEST(rel_diff(x.h, ref_a[i].h) == 0.0);
    BOOST_TEST(rel_diff(y.Q, ref_b[i].Q) == 0.0);
    BOOST_TEST(rel_diff(y.gamma, ref_b[i].gamma, 1.0) == 0.0);
  }
  // Tangents alternating with the same number of directions.
  Eigen::MatrixXd V = Eigen::MatrixXd::Identity(5, 2);
  Eigen::MatrixXd M, dh1, dh2, dh3;
  Eigen::VectorXd h;
  std::vector<Eigen::MatrixXd> dM;
  ea->kinetic_terms_tangent(0.1, q[0], qd[0], V, M, h, dM, dh1);
  eb->kinetic_terms_tangent(0.1, q[0], qd[0], V, M, h, dM, dh2);
  ea->kinetic_terms_tangent(0.1, q[0], qd[0], V, M, h, dM, dh3);
  BOOST_TEST(rel_diff(dh1, dh3) == 0.0);
  BOOST_TEST(rel_diff(dh1, dh2) > 0.1);
  // Two threads, each on both models.
  bool same[2] = {true, true};
  auto work = [&](int k) {
    for (int rep = 0; rep < 20; ++rep) {
      const auto x = all(k == 0 ? *ea : *eb);
      const auto y = all(k == 0 ? *eb : *ea);
      const auto& rx = k == 0 ? ref_a : ref_b;
      const auto& ry = k == 0 ? ref_b : ref_a;
      for (int i = 0; i < 50; ++i) {
        same[k] = same[k] && rel_diff(x[i].h, rx[i].h) == 0.0 && rel_diff(y[i].M, ry[i].M) == 0.0;
      }
    }
  };
  std::thread t0(work, 0), t1(work, 1);
  t0.join();
  t1.join();
  BOOST_TEST(same[0]);
  BOOST_TEST(same[1]);
}

// Loading from several threads at once is safe (GiNaC is serialized inside), and every load
// gives the same tape, whatever GiNaC did before (its symbol serials, and so its ordering of
// sums and products, change from load to load): bit-identical results in every process.
BOOST_AUTO_TEST_CASE(descriptions_load_concurrently_and_identically) {
  std::vector<std::shared_ptr<const ModelDescription>> d(4);
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k) {
    threads.emplace_back([&, k] { d[k] = load_model_file(model_path("sieve_1995.toml")); });
  }
  for (auto& t : threads) t.join();
  Eigen::VectorXd q0(6), q(6), qd(6);
  q0 << 0, 0, 0, 0.4, 0.15, 0;
  q << 1e-3, -2e-3, 0.1, 0.3, 0.15, 1.0;
  qd << 0.1, -0.2, 0.3, 0.2, 0.0, -2.0;
  const Evaluation ref = evaluate(*d[0]->instantiate({}, q0, 0.0), {0, 1}, 0.01, q, qd);
  for (int k = 1; k < 4; ++k) {
    const Tape& a = d[0]->compiled().tape;
    const Tape& b = d[k]->compiled().tape;
    BOOST_TEST(a.instruction_count() == b.instruction_count());
    bool same_code = a.blocks.size() == b.blocks.size();
    for (std::size_t i = 0; same_code && i < a.blocks.size(); ++i) {
      same_code = a.blocks[i].code.size() == b.blocks[i].code.size();
      for (std::size_t j = 0; same_code && j < a.blocks[i].code.size(); ++j) {
        const Instr &x = a.blocks[i].code[j], &y = b.blocks[i].code[j];
        same_code = x.op == y.op && x.dst == y.dst && x.a == y.a && x.b == y.b;
      }
    }
    BOOST_TEST(same_code);
    const Evaluation e = evaluate(*d[k]->instantiate({}, q0, 0.0), {0, 1}, 0.01, q, qd);
    BOOST_TEST(rel_diff(e.M, ref.M) == 0.0);
    BOOST_TEST(rel_diff(e.h, ref.h) == 0.0);
    BOOST_TEST(rel_diff(e.Q, ref.Q) == 0.0);
  }
}
