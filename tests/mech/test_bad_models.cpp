// Bad models and constraint sets give clear errors that name the cause: singular mass matrix,
// dependent or contradictory constraints, NaN in forces (at the start and during a run),
// unknown names, broken constant_row promises, bad registry input.
#define BOOST_TEST_MODULE mech_bad_models
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"

using namespace pcsim;
using namespace pcsim::mech;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// z has no inertia: M = diag(m, 0) is singular.
struct NoInertia {
  std::string name() const { return "no_inertia"; }
  std::vector<std::string> coordinates() const { return {"x", "z"}; }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * 2.0 * qd[0] * qd[0];
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    return 0.5 * q[1] * q[1];
  }
};

// Q_y becomes NaN after t_bad.
struct NanForce {
  double t_bad;
  std::string name() const { return "nan_force"; }
  std::vector<std::string> coordinates() const { return {"x", "y"}; }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    return 0.5 * (q[0] * q[0] + q[1] * q[1]);
  }
  template <class S> VecX<S> applied_forces(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    VecX<S> Q = VecX<S>::Zero(2);
    if (t >= t_bad) Q[1] = S(std::numeric_limits<double>::quiet_NaN());
    return Q;
  }
};

// Masses of 1e308 kg on springs of 1e308 N/m: M, h and Q are finite, but their sum overflows.
struct HugeButFinite {
  std::string name() const { return "huge_but_finite"; }
  std::vector<std::string> coordinates() const { return {"x", "y"}; }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5e308 * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    return 0.5e308 * (q[0] * q[0] + q[1] * q[1]);
  }
};

// Declares its row constant although it depends on q.
struct FalsePromise {
  std::string name() const { return "false_promise"; }
  std::vector<std::string> coordinates() const { return {"x", "y"}; }
  std::vector<ConstraintInfo> constraints() const {
    return {{"circle", ConstraintKind::holonomic, true}};
  }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const { return q[1]; }
  template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const {
    return q[0] * q[0] + q[1] * q[1] - 1.0;
  }
};

Eigen::VectorXd slider_crank_q() {
  // A consistent configuration at phi1 = 0: A = (l1, 0), B = (l1 + l2, 0).
  const ModelParameters p = default_parameters("slider_crank");
  const double l1 = p.at("l1"), l2 = p.at("l2");
  Eigen::VectorXd q(5);
  q << 0.0, l1 + 0.5 * l2, 0.0, 0.0, l1 + l2;
  return q;
}

}  // namespace

BOOST_AUTO_TEST_CASE(singular_mass_matrix_is_reported_naming_the_coordinate) {
  const auto model = make_model(NoInertia{});
  SimulationOptions o;
  const SimulationResult r = simulate(*model, Eigen::Vector2d(0, 1), Eigen::Vector2d(0, 0), o);
  BOOST_TEST(static_cast<int>(r.status) == static_cast<int>(SimulationStatus::invalid_model));
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::singular_mass_matrix));
  BOOST_TEST_MESSAGE(r.message);
  BOOST_TEST(contains(r.message, "mass matrix"));
  BOOST_TEST(contains(r.message, "'z'"));
  BOOST_TEST(!contains(r.message, "'x'"));
  const ReactionResult rr = reactions(*model, {}, 0.0, Eigen::Vector2d(0, 1), Eigen::Vector2d(0, 0));
  BOOST_TEST(static_cast<int>(rr.issue) == static_cast<int>(ModelIssue::singular_mass_matrix));
}

BOOST_AUTO_TEST_CASE(redundant_constraints_are_named_and_run_and_a_row_listed_twice_is_refused) {
  const auto model = create_model("slider_crank");
  for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
    SimulationOptions o;
    o.kernel = kernel;
    o.active_constraints = {"A_x", "A_y", "B_x", "B_y", "B_y_copy"};
    // Issue 21: dependent but consistent rows run (R is unique; the split by constraint is the
    // minimum-norm one); check_model names the redundant row without refusing it.
    const SimulationResult r = simulate(*model, slider_crank_q(), Eigen::VectorXd::Zero(5), o);
    BOOST_TEST_MESSAGE(r.message);
    BOOST_TEST(static_cast<int>(r.status) == static_cast<int>(SimulationStatus::success));
    const CheckResult c = check_model(*model, o.active_constraints, 0.0, slider_crank_q(),
                                      Eigen::VectorXd::Zero(5), kernel);
    BOOST_TEST(contains(c.message, "'B_y_copy' is redundant"));
    BOOST_TEST(contains(c.message, "'B_y'"));  // it is a multiple of B_y alone
    BOOST_TEST(!contains(c.message, "'A_x'"));
  }
  // The same constraint twice is dependent too.
  SimulationOptions o;
  o.active_constraints = {"A_x", "A_x"};
  const SimulationResult r = simulate(*model, slider_crank_q(), Eigen::VectorXd::Zero(5), o);
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::dependent_constraints));
  BOOST_TEST(contains(r.message, "'A_x'"));
}

BOOST_AUTO_TEST_CASE(contradictory_constraints_are_reported_by_name) {
  const auto model = create_model("slider_crank");
  SimulationOptions o;
  o.active_constraints = {"A_x", "A_y", "B_x", "B_y", "B_y_shifted"};
  const SimulationResult r = simulate(*model, slider_crank_q(), Eigen::VectorXd::Zero(5), o);
  BOOST_TEST_MESSAGE(r.message);
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::inconsistent_constraints));
  BOOST_TEST(contains(r.message, "'B_y_shifted' contradicts 'B_y'"));
}

BOOST_AUTO_TEST_CASE(nan_in_forces_at_the_start_is_reported_naming_the_coordinate) {
  const auto model = make_model(NanForce{0.0});
  SimulationOptions o;
  const SimulationResult r = simulate(*model, Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 0), o);
  BOOST_TEST_MESSAGE(r.message);
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::non_finite));
  BOOST_TEST(contains(r.message, "generalized forces"));
  BOOST_TEST(contains(r.message, "'y'"));
  BOOST_TEST(!contains(r.message, "'x'"));
}

BOOST_AUTO_TEST_CASE(nan_in_forces_during_the_run_ends_it_with_the_cause) {
  const auto model = make_model(NanForce{0.5});
  SimulationOptions o;
  o.t_end = 2.0;
  o.kernel = Kernel::cpp;
  const SimulationResult r = simulate(*model, Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 0), o);
  BOOST_TEST_MESSAGE(to_string(r.status) << ": " << r.message);
  BOOST_TEST(static_cast<int>(r.status) == static_cast<int>(SimulationStatus::model_failed));
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::non_finite));
  BOOST_TEST(contains(r.message, "generalized forces"));
  BOOST_TEST(r.t <= 0.5 + 1e-12);
  BOOST_TEST(r.t > 0.4);
}

// Dynamics::evaluate decides finiteness by one sum over M, h, Q and the rows; a sum that
// overflows must fall back to the checks of the parts, which pass: huge values are not NaN.
// Oracle: x(t) = cos t (ω² = k/m = 1) at t = 1.
BOOST_AUTO_TEST_CASE(huge_finite_values_whose_sum_overflows_are_not_reported_non_finite) {
  const auto model = make_model(HugeButFinite{});
  SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = o.atol = 1e-10;
  const SimulationResult r = simulate(*model, Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 0), o);
  BOOST_TEST_MESSAGE(r.message);
  BOOST_TEST(static_cast<int>(r.status) == static_cast<int>(SimulationStatus::success));
  BOOST_TEST(r.q_end[0] == std::cos(1.0), boost::test_tools::tolerance(1e-8));
}

BOOST_AUTO_TEST_CASE(unknown_constraint_names_list_the_offered_ones) {
  const auto model = create_model("pendulum");
  SimulationOptions o;
  o.active_constraints = {"lenght"};
  const SimulationResult r = simulate(*model, Eigen::Vector2d(0, -1), Eigen::Vector2d(0, 0), o);
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::unknown_constraint));
  BOOST_TEST(contains(r.message, "'lenght'"));
  BOOST_TEST(contains(r.message, "'length'"));
}

BOOST_AUTO_TEST_CASE(a_broken_constant_row_promise_is_detected) {
  const auto model = make_model(FalsePromise{});
  SimulationOptions o;
  o.active_constraints = {"circle"};
  const SimulationResult r = simulate(*model, Eigen::Vector2d(0, -1), Eigen::Vector2d(0, 0), o);
  BOOST_TEST(static_cast<int>(r.issue) == static_cast<int>(ModelIssue::not_constant_row));
  BOOST_TEST(contains(r.message, "'circle'"));
}

BOOST_AUTO_TEST_CASE(registry_rejects_unknown_models_parameters_and_nonphysical_values) {
  BOOST_CHECK_EXCEPTION(create_model("pendulun"), InputError, [](const InputError& e) {
    return contains(e.what(), "'pendulun'") && contains(e.what(), "pendulum");
  });
  BOOST_CHECK_EXCEPTION(create_model("pendulum", {{"mass", 1.0}}), InputError,
                        [](const InputError& e) { return contains(e.what(), "'mass'"); });
  BOOST_CHECK_EXCEPTION(create_model("rolling_disk", {{"r", -0.1}}), InputError,
                        [](const InputError& e) { return contains(e.what(), "'r' must be > 0"); });
  const std::vector<std::string> names = model_names();
  BOOST_TEST(names.size() >= 3u);
  // Run-time registration (for components built after mech).
  register_model("free_particle_test",
                 [](const ModelParameters& p) { return make_model(NanForce{1e300}); });
  BOOST_TEST(create_model("free_particle_test")->n() == 2);
}
