// The double pendulum written twice (models/double_pendulum.toml: absolute coordinates x1 y1
// x2 y2 with two holonomic rod constraints; models/double_pendulum_minimal.toml: two angles, no
// constraints): the positions of both runs agree to integrator accuracy over a run in which
// the motion is chaotic, and the constraint reactions of the absolute model are the rod
// tensions that the minimal model computes from Newton's law on each mass.
#define BOOST_TEST_MODULE modelfile_double_pendulum
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

const double L1 = 1.0, L2 = 0.8;  // lengths; masses m1 = 1.0, m2 = 1.5
const std::map<std::string, double> kParameters = {
    {"m1", 1.0}, {"m2", 1.5}, {"L1", L1}, {"L2", L2}, {"g", 9.81}};

// Absolute state (x1, y1, x2, y2) and its velocities from the angles and their rates.
void absolute_state(const Eigen::VectorXd& phi, const Eigen::VectorXd& phid, Eigen::VectorXd& q,
                    Eigen::VectorXd& qd) {
  q.resize(4);
  qd.resize(4);
  const double s1 = std::sin(phi[0]), c1 = std::cos(phi[0]);
  const double s2 = std::sin(phi[1]), c2 = std::cos(phi[1]);
  q << L1 * s1, -L1 * c1, L1 * s1 + L2 * s2, -L1 * c1 - L2 * c2;
  qd << L1 * c1 * phid[0], L1 * s1 * phid[0], L1 * c1 * phid[0] + L2 * c2 * phid[1],
      L1 * s1 * phid[0] + L2 * s2 * phid[1];
}

// The mass positions (x1, y1, x2, y2) at the times 0, dt, 2 dt, ..., t_end of one run, read
// from the integrator's dense output. For the minimal model they are its outputs x1 .. y2.
struct Run {
  std::vector<Eigen::VectorXd> positions;
  mech::SimulationResult result;
};

Run run(const mech::Model& model, const std::vector<std::string>& active, const Eigen::VectorXd& q0,
        const Eigen::VectorXd& qd0, double t_end, double dt, double rtol, bool minimal) {
  Run out;
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = rtol;
  o.atol = rtol;
  o.active_constraints = active;
  o.kernel = Kernel::cpp;
  const int count = static_cast<int>(std::lround(t_end / dt));
  int next = 0;
  out.result = mech::simulate(model, q0, qd0, o, [&](const mech::StepView& v) {
    while (next <= count && next * dt <= v.t + 1e-12) {
      const mech::Sample s = v.at(std::min(next * dt, v.t));
      out.positions.push_back(minimal ? Eigen::VectorXd(s.derived.head(4)) : s.q);
      ++next;
    }
    return true;
  });
  return out;
}

double max_difference(const Run& a, const Run& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < std::min(a.positions.size(), b.positions.size()); ++k) {
    d = std::max(d, (a.positions[k] - b.positions[k]).cwiseAbs().maxCoeff());
  }
  return d;
}

}  // namespace

// A swing from phi = (2.0, 2.6) rad at rest (the lower mass goes over the top): over 6 s a
// change of 1e-9 rad in the start grows by about four orders of magnitude, so the run is
// chaotic. Each formulation's global error is estimated by rerunning it at a 100 times tighter
// tolerance; the two formulations must agree to within 10 times the sum of those estimates
// (plus 1e-9 m for the dense output): to integrator accuracy, far below what the chaos would
// make of any difference in the physics.
BOOST_AUTO_TEST_CASE(absolute_and_minimal_coordinates_agree_to_integrator_accuracy) {
  const auto abs_model = load_model_file(model_path("double_pendulum.toml"))->instantiate(kParameters);
  const auto min_model =
      load_model_file(model_path("double_pendulum_minimal.toml"))->instantiate(kParameters);
  Eigen::VectorXd phi(2), phid = Eigen::VectorXd::Zero(2), q, qd;
  phi << 2.0, 2.6;
  absolute_state(phi, phid, q, qd);
  const double t_end = 6.0, dt = 0.05;
  const std::vector<std::string> rods = {"rod1", "rod2"};
  const Run a = run(*abs_model, rods, q, qd, t_end, dt, 1e-9, false);
  const Run m = run(*min_model, {}, phi, phid, t_end, dt, 1e-9, true);
  const Run a_tight = run(*abs_model, rods, q, qd, t_end, dt, 1e-11, false);
  const Run m_tight = run(*min_model, {}, phi, phid, t_end, dt, 1e-11, true);
  Eigen::VectorXd phi_p = phi;
  phi_p[0] += 1e-9;
  const Run m_perturbed = run(*min_model, {}, phi_p, phid, t_end, dt, 1e-11, true);
  for (const Run* r : {&a, &m, &a_tight, &m_tight, &m_perturbed}) {
    BOOST_REQUIRE(r->result.status == mech::SimulationStatus::success);
    BOOST_REQUIRE(r->positions.size() == static_cast<std::size_t>(std::lround(t_end / dt)) + 1);
  }
  const double cross = max_difference(a, m);
  const double err_a = max_difference(a, a_tight), err_m = max_difference(m, m_tight);
  const double growth = max_difference(m_perturbed, m_tight) / 1e-9;
  BOOST_TEST_MESSAGE("absolute vs minimal: max |dpos| = " << cross << " m; error estimates "
                     << err_a << " (absolute), " << err_m << " (minimal); a 1e-9 start "
                     "change grows by " << growth);
  BOOST_TEST(growth > 1e3);  // chaotic enough
  BOOST_TEST(cross <= 10 * (err_a + err_m) + 1e-9);
  BOOST_TEST(max_difference(a_tight, m_tight) <= 10 * (err_a + err_m) + 1e-9);
  // The absolute run stays on its constraints (projection after every step).
  BOOST_TEST(a.result.residual_pos_max < 1e-12);
}

// At states along a swing, the reactions of the absolute model (compatibility, rods active)
// are R_mass2 = −T2 e2 and R_mass1 = −T1 e1 + T2 e2, with the tensions T1, T2 of the minimal
// model (outputs computed from its accelerations) and e_i the rod directions. Tolerance 1e-10
// relative to the largest reaction: two linear solves of condition < 1e2 and the minimal
// model's accelerations.
BOOST_AUTO_TEST_CASE(constraint_reactions_equal_the_rod_tensions_of_the_minimal_model) {
  const auto abs_model = load_model_file(model_path("double_pendulum.toml"))->instantiate(kParameters);
  const auto min_model =
      load_model_file(model_path("double_pendulum_minimal.toml"))->instantiate(kParameters);
  BOOST_REQUIRE(min_model->derived_names() ==
                (std::vector<std::string>{"x1", "y1", "x2", "y2", "tension1", "tension2"}));
  BOOST_REQUIRE(abs_model->derived_names() == (std::vector<std::string>{"tension1", "tension2"}));
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd phi(2), phid(2);
    phi << 3 * uniform(rng), 3 * uniform(rng);
    phid << 4 * uniform(rng), 4 * uniform(rng);
    const mech::ReactionResult rm = mech::reactions(*min_model, {}, 0.0, phi, phid);
    BOOST_REQUIRE(rm.issue == mech::ModelIssue::none);
    Eigen::VectorXd out;
    min_model->derived(0.0, phi, phid, rm.qdd, rm.R, out);
    const double T1 = out[4], T2 = out[5];
    const Eigen::Vector2d e1(std::sin(phi[0]), -std::cos(phi[0]));
    const Eigen::Vector2d e2(std::sin(phi[1]), -std::cos(phi[1]));
    Eigen::VectorXd expected(4);
    expected << -T1 * e1 + T2 * e2, -T2 * e2;

    Eigen::VectorXd q, qd;
    absolute_state(phi, phid, q, qd);
    const mech::ReactionResult ra = mech::reactions(*abs_model, {"rod1", "rod2"}, 0.0, q, qd);
    BOOST_REQUIRE(ra.issue == mech::ModelIssue::none);
    BOOST_TEST_CONTEXT("trial " << trial << " T1 " << T1 << " T2 " << T2) {
      BOOST_TEST(rel_diff(ra.R, expected) < 1e-10);
      // The absolute model's own tension outputs, from its reactions.
      Eigen::VectorXd tensions;
      abs_model->derived(0.0, q, qd, ra.qdd, ra.R, tensions);
      BOOST_TEST(std::abs(tensions[0] - T1) < 1e-10 * expected.cwiseAbs().maxCoeff());
      BOOST_TEST(std::abs(tensions[1] - T2) < 1e-10 * expected.cwiseAbs().maxCoeff());
      // The accelerations agree too: the angles' second derivatives mapped to the masses.
      const Eigen::Vector2d a1 =
          L1 * (rm.qdd[0] * Eigen::Vector2d(e1[1] * -1, e1[0]) - phid[0] * phid[0] * e1);
      BOOST_TEST((ra.qdd.head(2) - a1).cwiseAbs().maxCoeff() < 1e-10 * ra.qdd.cwiseAbs().maxCoeff());
    }
  }
}
