// A nonholonomic constraint in the paper's velocity form, from a model file
// (models/knife_edge.toml: sin(psi) x_d - cos(psi) y_d = 0), against the closed-form motion: with
// a push F along the heading and no torque, the heading turns uniformly, psi = psi0 + w t, the
// speed grows uniformly, v = v0 + (F/m) t, and
//   x(t) = [(v0 + a s) sin(psi0 + w s)/w + a cos(psi0 + w s)/w^2] from 0 to t,
//   y(t) = [-(v0 + a s) cos(psi0 + w s)/w + a sin(psi0 + w s)/w^2] from 0 to t,
// with the lateral reaction m v psi_d that bends the path. With a torque, psi is quadratic in t
// and the speed and lateral force keep their closed forms.
#define BOOST_TEST_MODULE modelfile_knife_edge
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

struct Errors {
  double position = 0, heading = 0, speed = 0, lateral = 0, residual_vel = 0;
};

// Runs the knife edge from (0, 0, psi0) with speed v0 and turning rate w0 and compares every
// accepted step with the closed forms (x, y only when tau = 0).
Errors run(double m, double J, double F, double tau, double psi0, double v0, double w0,
           double t_end, double rtol) {
  const auto desc = load_model_file(model_path("knife_edge.toml"));
  const auto model = desc->instantiate({{"m", m}, {"J", J}, {"F", F}, {"tau", tau}});
  BOOST_REQUIRE(model->derived_names() == (std::vector<std::string>{"speed", "lateral"}));
  Eigen::VectorXd q(3), qd(3);
  q << 0, 0, psi0;
  qd << v0 * std::cos(psi0), v0 * std::sin(psi0), w0;
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = o.atol = rtol;
  o.kernel = Kernel::cpp;
  o.active_constraints = {"knife"};
  const double a = F / m, alpha = tau / J;
  Errors e;
  const mech::SimulationResult r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample s = v.at(v.t);
    const double t = s.t;
    const double psi = psi0 + w0 * t + 0.5 * alpha * t * t, w = w0 + alpha * t;
    const double speed = v0 + a * t;
    e.heading = std::max(e.heading, std::abs(s.q[2] - psi));
    e.speed = std::max(e.speed, std::abs(s.derived[0] - speed));
    e.lateral = std::max(e.lateral, std::abs(s.derived[1] - m * speed * w));
    // The reaction is the lateral force along the left normal (−sin psi, cos psi), no torque.
    e.lateral = std::max(e.lateral, std::abs(s.R[0] + m * speed * w * std::sin(psi)));
    e.lateral = std::max(e.lateral, std::abs(s.R[1] - m * speed * w * std::cos(psi)));
    e.lateral = std::max(e.lateral, std::abs(s.R[2]));
    e.residual_vel = std::max(e.residual_vel, s.residual_vel);
    if (tau == 0.0) {
      auto X = [&](double u) {
        return (v0 + a * u) * std::sin(psi0 + w0 * u) / w0 + a * std::cos(psi0 + w0 * u) / (w0 * w0);
      };
      auto Y = [&](double u) {
        return -(v0 + a * u) * std::cos(psi0 + w0 * u) / w0 + a * std::sin(psi0 + w0 * u) / (w0 * w0);
      };
      e.position = std::max(e.position, std::abs(s.q[0] - (X(t) - X(0))));
      e.position = std::max(e.position, std::abs(s.q[1] - (Y(t) - Y(0))));
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST(std::isnan(model->position_residual(0, 0.0, q)));  // no position-level form
  return e;
}

}  // namespace

// 5 s, about one turn (w = 1.2 rad/s), the speed growing from 0.7 to 1.95 m/s, at rtol = atol
// = 1e-10: the global error of the integration is of order 1e-9 over the run (a few steps'
// local errors, accumulated without growth: the motion is neutrally stable), so positions,
// heading and speed must agree to 1e-7 and the lateral force (m v w ~ 5 N) to 1e-6 N.
BOOST_AUTO_TEST_CASE(knife_edge_pushed_along_its_heading_follows_the_closed_form) {
  const Errors e = run(2.0, 0.1, 0.5, 0.0, 0.3, 0.7, 1.2, 5.0, 1e-10);
  BOOST_TEST_MESSAGE("knife edge, tau = 0: errors position " << e.position << " m, heading "
                     << e.heading << " rad, speed " << e.speed << " m/s, lateral "
                     << e.lateral << " N; max |g q_d + g0| " << e.residual_vel);
  BOOST_TEST(e.position < 1e-7);
  BOOST_TEST(e.heading < 1e-7);
  BOOST_TEST(e.speed < 1e-7);
  BOOST_TEST(e.lateral < 1e-6);
  BOOST_TEST(e.residual_vel < 1e-12);  // projected onto the constraint after every step
}

// With a torque the heading is psi0 + w0 t + tau t^2/(2 J); speed and lateral force as above.
BOOST_AUTO_TEST_CASE(knife_edge_with_a_torque_turns_quadratically) {
  const Errors e = run(2.0, 0.1, 0.5, 0.05, 0.3, 0.7, 1.2, 3.0, 1e-10);
  BOOST_TEST_MESSAGE("knife edge, tau = 0.05: errors heading " << e.heading << " rad, speed "
                     << e.speed << " m/s, lateral " << e.lateral << " N");
  BOOST_TEST(e.heading < 1e-7);
  BOOST_TEST(e.speed < 1e-7);
  BOOST_TEST(e.lateral < 1e-6);
}
