// The model files of the engine's validation models (models/pendulum.toml, rolling_disk.toml,
// slider_crank.toml) are the same systems as the C++ models of tests/mech/models: at random
// states they give the same M, h, Q, constraint rows, position residuals, reactions and derived
// quantities. The C++ models are derived by automatic differentiation, the files symbolically:
// two independent derivations of one Lagrangian.
#define BOOST_TEST_MODULE modelfile_builtin_models
#include <boost/test/unit_test.hpp>

#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

struct Pair {
  const char* name;
  std::vector<std::vector<std::string>> active_sets;  // constraint sets to compare reactions
};

const std::vector<Pair>& pairs() {
  static const std::vector<Pair> p = {
      {"pendulum", {{"length"}}},
      {"rolling_disk", {{"contact", "rolling"}, {"rolling"}, {"contact"}}},
      {"slider_crank", {{"A_x", "A_y", "B_x", "B_y"}, {"A_x", "A_y", "B_x"}}},
  };
  return p;
}

// Non-default parameter values (each changed, so a parameter read in the wrong place shows).
mech::ModelParameters changed(const mech::ModelParameters& defaults) {
  mech::ModelParameters p;
  double f = 1.1;
  for (const auto& [k, v] : defaults) {
    p[k] = v * f;
    f += 0.07;
  }
  return p;
}

}  // namespace

// Tolerance 1e-12 relative to each matrix's largest entry: the two derivations round
// differently, by a few ulps of the largest term (no cancellation beyond 1e2 in these models).
BOOST_AUTO_TEST_CASE(model_files_equal_the_cpp_models_at_random_states) {
  std::mt19937 rng(2026);
  for (const Pair& pr : pairs()) {
    BOOST_TEST_CONTEXT(pr.name) {
      const mech::ModelParameters params = changed(mech::default_parameters(pr.name));
      const auto cpp = mech::create_model(pr.name, params);
      const auto desc = load_model_file(model_path(std::string(pr.name) + ".toml"));
      const auto file = desc->instantiate(params);
      BOOST_REQUIRE(file->n() == cpp->n());
      BOOST_TEST(file->coordinates() == cpp->coordinates());
      BOOST_REQUIRE(file->constraints().size() == cpp->constraints().size());
      std::vector<int> all;
      for (std::size_t i = 0; i < cpp->constraints().size(); ++i) {
        BOOST_TEST(file->constraints()[i].name == cpp->constraints()[i].name);
        BOOST_TEST(static_cast<int>(file->constraints()[i].kind) ==
                   static_cast<int>(cpp->constraints()[i].kind));
        all.push_back(static_cast<int>(i));
      }
      for (int trial = 0; trial < 10; ++trial) {
        const int n = cpp->n();
        Eigen::VectorXd q(n), qd(n);
        for (int i = 0; i < n; ++i) {
          q[i] = 1.5 * uniform(rng);
          qd[i] = 2.0 * uniform(rng);
        }
        const double t = uniform(rng);
        const Evaluation a = evaluate(*file, all, t, q, qd);
        const Evaluation b = evaluate(*cpp, all, t, q, qd);
        BOOST_TEST(rel_diff(a.M, b.M) < 1e-12);
        BOOST_TEST(rel_diff(a.h, b.h, 1.0) < 1e-12);
        BOOST_TEST(rel_diff(a.Q, b.Q, 1.0) < 1e-12);
        BOOST_TEST(rel_diff(a.g, b.g) < 1e-12);
        BOOST_TEST(rel_diff(a.g0, b.g0, 1.0) < 1e-12);
        BOOST_TEST(rel_diff(a.gamma, b.gamma, 1.0) < 1e-12);
        for (int i : all) {
          const double pa = file->position_residual(i, t, q), pb = cpp->position_residual(i, t, q);
          if (std::isnan(pb)) {
            BOOST_TEST(std::isnan(pa));
          } else {
            BOOST_TEST(std::abs(pa - pb) <= 1e-12 * std::max(1.0, std::abs(pb)));
          }
        }
        for (const auto& active : pr.active_sets) {
          const mech::ReactionResult ra = mech::reactions(*file, active, t, q, qd);
          const mech::ReactionResult rb = mech::reactions(*cpp, active, t, q, qd);
          BOOST_REQUIRE(ra.issue == mech::ModelIssue::none);
          BOOST_REQUIRE(rb.issue == mech::ModelIssue::none);
          // Reactions pass through a linear solve: 1e-10 (condition numbers below ~1e2 here).
          BOOST_TEST(rel_diff(ra.R, rb.R, 1.0) < 1e-10);
          BOOST_TEST(rel_diff(ra.qdd, rb.qdd, 1.0) < 1e-10);
        }
      }
    }
  }
}

// The pendulum's derived "tension" (C++: −R·q/|q|) is the model file's output of that name.
BOOST_AUTO_TEST_CASE(pendulum_tension_output_equals_the_cpp_derived_quantity) {
  std::mt19937 rng(7);
  const auto cpp = mech::create_model("pendulum");
  const auto file = load_model_file(model_path("pendulum.toml"))->instantiate({});
  BOOST_REQUIRE(file->derived_names() == cpp->derived_names());
  for (int trial = 0; trial < 5; ++trial) {
    const double phi = 3 * uniform(rng);
    Eigen::VectorXd q(2), qd(2);
    q << std::sin(phi), -std::cos(phi);
    qd << uniform(rng), uniform(rng);
    const mech::ReactionResult r = mech::reactions(*file, {"length"}, 0.0, q, qd);
    Eigen::VectorXd a, b;
    file->derived(0.0, q, qd, r.qdd, r.R, a);
    cpp->derived(0.0, q, qd, r.qdd, r.R, b);
    BOOST_TEST(std::abs(a[0] - b[0]) < 1e-12 * std::max(1.0, std::abs(b[0])));
  }
}

// The offered-but-off constraints of the slider-crank (redundant B_y_copy, contradicting
// B_y_shifted) are reported by name, as for the C++ model.
BOOST_AUTO_TEST_CASE(slider_crank_file_reports_dependent_constraints_by_name) {
  const auto desc = load_model_file(model_path("slider_crank.toml"));
  BOOST_TEST(desc->default_active_constraints() ==
             (std::vector<std::string>{"A_x", "A_y", "B_x", "B_y"}));
  const auto file = desc->instantiate({});
  Eigen::VectorXd q(5), qd = Eigen::VectorXd::Zero(5);
  // A consistent state: crank at 0.3 rad, rod from A to B on the x axis.
  const double l1 = 0.2, l2 = 0.6, phi1 = 0.3;
  const double Ax = l1 * std::cos(phi1), Ay = l1 * std::sin(phi1);
  const double phi2 = -std::asin(Ay / l2);
  q << phi1, Ax + 0.5 * l2 * std::cos(phi2), Ay + 0.5 * l2 * std::sin(phi2), phi2,
      Ax + l2 * std::cos(phi2);
  const mech::CheckResult c =
      mech::check_model(*file, {"A_x", "A_y", "B_x", "B_y", "B_y_copy"}, 0.0, q, qd);
  BOOST_TEST_MESSAGE(c.message);
  // Issue 21: dependent but consistent rows are named, not refused.
  BOOST_TEST(static_cast<int>(c.issue) == static_cast<int>(mech::ModelIssue::none));
  BOOST_TEST(c.rank == 4);
  BOOST_TEST(c.message.find("'B_y_copy' is redundant") != std::string::npos);
}
