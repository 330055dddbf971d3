// The engine's exact Jacobian of the ODE form's right-hand side (mech/tangent.hpp): equal to
// central differences of the right-hand side at random states of every model file (an oracle
// only, with the difference's own error bounded), equal to the hand-derived Jacobian of the
// Cartesian pendulum, with Baumgarte terms, the constrained response to a force, and the
// refusal of models without tangents.
#define BOOST_TEST_MODULE steady_rhs_jacobian
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "mech/dynamics.hpp"
#include "mech/models/registry.hpp"
#include "mech/tangent.hpp"
#include "modelfile/model_file.hpp"
#include "steady/forced_model.hpp"

using namespace pcsim;

namespace {

std::shared_ptr<const modelfile::ModelDescription> load(const std::string& file) {
  return modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/models/" + file);
}

double uniform(std::mt19937& rng) { return std::uniform_real_distribution<double>(-1, 1)(rng); }

// q̈ of the ODE form by the engine's structured compatibility solve.
Eigen::VectorXd qdd_of(mech::Dynamics& dyn, const mech::ActiveSet& set, double t,
                       const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  BOOST_REQUIRE(dyn.evaluate(set, t, q, qd) == mech::ModelIssue::none);
  BOOST_REQUIRE(dyn.solve(mech::ReactionMethod::compatibility_structured) == mech::ModelIssue::none);
  return dyn.qdd;
}

// Central differences of f(t, y) = (q̇, q̈) in y and t, with steps h_i = 1e-5 (1 + |y_i|) and
// h_t = 1e-7 (the sieve's excitation varies at omega = 280 rad/s: its truncation error
// (h omega)^2/6 needs the smaller step). Their error: truncation h² |f'''|/6 and rounding
// eps |f|/h, both below 1e-8 of the scale of these smooth models; the comparison tolerance 1e-6
// leaves a margin of 100.
void central_differences(mech::Dynamics& dyn, const mech::ActiveSet& set, double t,
                         const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::MatrixXd& J,
                         Eigen::VectorXd& dfdt) {
  const int n = static_cast<int>(q.size());
  Eigen::VectorXd y(2 * n);
  y << q, qd;
  J.setZero(2 * n, 2 * n);
  J.topRightCorner(n, n).setIdentity();
  for (int i = 0; i <= 2 * n; ++i) {
    const double base = i < 2 * n ? y[i] : t;
    const double h = i < 2 * n ? 1e-5 * (1 + std::abs(base)) : 1e-7;
    Eigen::VectorXd yp = y, ym = y;
    double tp = t, tm = t;
    if (i < 2 * n) {
      yp[i] += h;
      ym[i] -= h;
    } else {
      tp += h;
      tm -= h;
    }
    const Eigen::VectorXd d = (qdd_of(dyn, set, tp, yp.head(n), yp.tail(n)) -
                               qdd_of(dyn, set, tm, ym.head(n), ym.tail(n))) /
                              (2 * h);
    if (i < 2 * n) J.block(n, i, n, 1) = d;
    else {
      dfdt = Eigen::VectorXd::Zero(2 * n);
      dfdt.tail(n) = d;
    }
  }
}

double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

struct ModelCase {
  std::string file;
  std::vector<std::string> active;
  double position_scale;  ///< random coordinates in [-scale, scale] (plus the offsets below)
};

}  // namespace

BOOST_AUTO_TEST_CASE(exact_jacobian_equals_central_differences_at_random_states_of_every_model_file) {
  const std::vector<ModelCase> cases = {
      {"sieve_1995.toml", {"contact", "rolling"}, 0.3},
      {"sieve_1995.toml", {"contact", "rolling", "lock_theta"}, 0.3},
      {"sieve_1995.toml", {}, 0.3},
      {"pendulum.toml", {"length"}, 1.0},
      {"rolling_disk.toml", {"contact", "rolling"}, 1.0},
      {"slider_crank.toml", {"A_x", "A_y", "B_x", "B_y"}, 1.0},
      {"double_pendulum.toml", {"rod1", "rod2"}, 1.0},
      {"knife_edge.toml", {"knife"}, 1.0},
  };
  std::mt19937 rng(1303);
  double worst = 0;
  for (const auto& c : cases) {
    const auto d = load(c.file);
    const int n = d->n();
    for (int trial = 0; trial < 6; ++trial) {
      Eigen::VectorXd q(n), qd(n);
      for (int i = 0; i < n; ++i) {
        q[i] = c.position_scale * uniform(rng) + (c.file == "sieve_1995.toml" && i == 4 ? 0.15 : 0.0);
        qd[i] = uniform(rng);
      }
      const double t = 0.1 * (1 + uniform(rng));
      const auto model = d->instantiate({}, q, 0.0);
      std::vector<int> rows;
      for (const auto& a : c.active) rows.push_back(model->constraint_index(a));
      const mech::ActiveSet set = mech::ActiveSet::of(*model, rows);
      mech::RhsTangent tan(*model);
      Eigen::MatrixXd J;
      Eigen::VectorXd dfdt;
      BOOST_REQUIRE(tan.jacobian(set, t, q, qd, J, &dfdt) == mech::ModelIssue::none);
      mech::Dynamics dyn(*model, Kernel::cpp);
      Eigen::MatrixXd Jfd;
      Eigen::VectorXd dfdt_fd;
      central_differences(dyn, set, t, q, qd, Jfd, dfdt_fd);
      BOOST_TEST_CONTEXT(c.file << " with " << c.active.size() << " constraints, trial " << trial) {
        BOOST_TEST(rel_diff(J, Jfd) < 1e-6);
        BOOST_TEST(rel_diff(dfdt, dfdt_fd) < 1e-6);
        worst = std::max({worst, rel_diff(J, Jfd), rel_diff(dfdt, dfdt_fd)});
        // The values equal the engine's own solve.
        BOOST_TEST(rel_diff(tan.qdd, qdd_of(dyn, set, t, q, qd)) < 1e-13);
      }
    }
  }
  BOOST_TEST_MESSAGE("largest difference to the central differences: " << worst);
}

BOOST_AUTO_TEST_CASE(exact_jacobian_equals_the_hand_derived_jacobian_of_the_pendulum) {
  // Cartesian pendulum, x² + y² = L²: q̈ = (0, −g) + (x, y) c with c = (g y − v²)/r²
  // (r² = x² + y², v² = ẋ² + ẏ²), differentiated by hand. Exact: agreement to rounding.
  const auto d = load("pendulum.toml");
  const double g = 9.81;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Vector2d q(uniform(rng), uniform(rng)), qd(2 * uniform(rng), 2 * uniform(rng));
    const auto model = d->instantiate({{"m", 1.0 + trial}, {"L", 1.3}});
    const mech::ActiveSet set = mech::ActiveSet::of(*model, {0});
    mech::RhsTangent tan(*model);
    Eigen::MatrixXd J;
    BOOST_REQUIRE(tan.jacobian(set, 0.0, q, qd, J) == mech::ModelIssue::none);
    const double x = q[0], y = q[1], xd = qd[0], yd = qd[1];
    const double r2 = x * x + y * y, v2 = xd * xd + yd * yd;
    const double c = (g * y - v2) / r2;
    const double cx = -2 * x * c / r2, cy = g / r2 - 2 * y * c / r2;
    const double cxd = -2 * xd / r2, cyd = -2 * yd / r2;
    Eigen::MatrixXd Je = Eigen::MatrixXd::Zero(4, 4);
    Je(0, 2) = Je(1, 3) = 1;
    Je.row(2) << c + x * cx, x * cy, x * cxd, x * cyd;
    Je.row(3) << y * cx, c + y * cy, y * cxd, y * cyd;
    BOOST_TEST(rel_diff(J, Je) < 1e-13);
    BOOST_TEST(std::abs(tan.qdd[0] - x * c) < 1e-13 * (1 + std::abs(x * c)));
    BOOST_TEST(std::abs(tan.qdd[1] - (-g + y * c)) < 1e-13 * (1 + g));
  }
}

BOOST_AUTO_TEST_CASE(baumgarte_terms_are_differentiated_too) {
  const auto d = load("double_pendulum.toml");
  std::mt19937 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q(4), qd(4);
    for (int i = 0; i < 4; ++i) q[i] = uniform(rng), qd[i] = uniform(rng);
    const auto model = d->instantiate({});
    const mech::ActiveSet set = mech::ActiveSet::of(*model, {0, 1});
    mech::RhsTangent tan(*model, mech::Stabilization::baumgarte, 3.0, 5.0);
    Eigen::MatrixXd J;
    Eigen::VectorXd dfdt;
    BOOST_REQUIRE(tan.jacobian(set, 0.2, q, qd, J, &dfdt) == mech::ModelIssue::none);
    mech::Dynamics dyn(*model, Kernel::cpp, mech::Stabilization::baumgarte, 3.0, 5.0);
    Eigen::MatrixXd Jfd;
    Eigen::VectorXd dfdt_fd;
    central_differences(dyn, set, 0.2, q, qd, Jfd, dfdt_fd);
    BOOST_TEST(rel_diff(J, Jfd) < 1e-6);
  }
}

BOOST_AUTO_TEST_CASE(constrained_response_equals_the_change_of_the_accelerations_under_a_force) {
  // respond(B) is ∂q̈/∂F for a generalized force F added to Q: compare with the engine's q̈ of
  // the model with F added (ForcedModel), at F and -F (q̈ is affine in F: exact to rounding).
  const auto d = load("sieve_1995.toml");
  Eigen::VectorXd q(6), qd(6);
  q << 1e-3, -2e-3, 1e-2, 0.3, 0.15, 0.2;
  qd << 0.1, -0.2, 0.05, 0.3, 0.0, -3.0;
  const auto model = d->instantiate({}, q, 0.0);
  const std::vector<int> rows = {model->constraint_index("contact"), model->constraint_index("rolling")};
  const mech::ActiveSet set = mech::ActiveSet::of(*model, rows);
  mech::RhsTangent tan(*model);
  BOOST_REQUIRE(tan.evaluate(set, 0.01, q, qd, Eigen::MatrixXd(13, 0)) == mech::ModelIssue::none);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 2), X, L;
  B(3, 0) = 1.0;  // a force on s
  B(0, 1) = 1.0;  // a force on x
  tan.respond(B, X, &L);
  for (int j = 0; j < 2; ++j) {
    const int coord = j == 0 ? 3 : 0;
    const double F = 2.0;
    const auto plus = steady::with_forces(model, {coord}, Eigen::VectorXd::Constant(1, F));
    const auto minus = steady::with_forces(model, {coord}, Eigen::VectorXd::Constant(1, -F));
    const mech::ActiveSet sp = mech::ActiveSet::of(*plus, rows), sm = mech::ActiveSet::of(*minus, rows);
    mech::Dynamics dp(*plus, Kernel::cpp), dm(*minus, Kernel::cpp);
    const Eigen::VectorXd ap = qdd_of(dp, sp, 0.01, q, qd), am = qdd_of(dm, sm, 0.01, q, qd);
    const Eigen::VectorXd dq = (ap - am) / (2 * F);
    // The quotient's own error is the rounding of q̈ (|q̈| up to ~1e3 at this state) over 2F:
    // 100 eps |q̈| / (2F), relative to the response's size.
    const double tol = 100 * 2.2e-16 * std::max(ap.cwiseAbs().maxCoeff(), am.cwiseAbs().maxCoeff()) /
                       (2 * F) / dq.cwiseAbs().maxCoeff();
    BOOST_TEST(rel_diff(X.col(j), dq) < std::max(tol, 1e-13));
    // The response keeps the constraints: g X = 0 (contact u, rolling s + r phi).
    BOOST_TEST(std::abs(X(4, j)) < 1e-14);
    BOOST_TEST(std::abs(X(3, j) + 0.1 * X(5, j)) < 1e-14 * (1 + X.col(j).norm()));
  }
}

BOOST_AUTO_TEST_CASE(models_without_tangents_are_refused_by_name) {
  const auto model = mech::create_model("pendulum");  // the C++ AD model
  BOOST_TEST(!model->has_tangents());
  try {
    mech::RhsTangent tan(*model);
    BOOST_FAIL("a model without tangents was accepted");
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    BOOST_TEST(what.find("'pendulum' has no exact tangents") != std::string::npos);
    BOOST_TEST(what.find("model file") != std::string::npos);
  }
}
