// Energy over every run of the contact problems: kinetic + potential + energy dissipated so far
// (impacts: the events' -Lambda (v+ + v-)/2; sliding friction: the integral of
// mu_k lambda_n |v_t|) stays equal to the initial energy. Checked at every accepted step as
// E(t) + impact losses up to t, which may fall below E0 only by the friction work of the run,
// and at the end as the full balance. Tolerance 1e-7 of the initial energy at rtol = atol =
// 1e-10: Radau works to 0.1 rtol^(2/3) = 2.2e-8 internally (docs/radau.md), and the rocking
// block's rotation is not polynomial, so its energy carries that error (observed 1e-8 of E0);
// the other problems are polynomial between events and balance to 1e-14.
#define BOOST_TEST_MODULE switching_energy
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <functional>

#include "switching_util.hpp"

using namespace switching_test;

namespace {

constexpr double kG = 9.81;

struct Case {
  std::string name, stem;
  std::map<std::string, double> p;
  Eigen::VectorXd q0, qd0, M;  // M: the (diagonal) mass matrix
  std::function<double(const Eigen::VectorXd&)> V;
  double t_end;
};

void check_balance(const Case& c) {
  auto m = contact_model(c.stem, c.p, c.q0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  Trace tr;
  const auto r = run(*m, c.q0, c.qd0, c.t_end, o, {}, &tr);
  BOOST_TEST_CONTEXT(c.name) {
    BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
    auto E = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
      return 0.5 * qd.dot(c.M.asDiagonal() * qd) + c.V(q);
    };
    const double E0 = E(tr.q.front(), tr.qd.front());
    double friction = 0.0, impacts = 0.0;
    for (const auto& st : r.contacts) {
      friction += st.run.energy_friction;
      impacts += st.run.energy_impacts;
    }
    const double scale = std::max(1.0, std::abs(E0));
    const double tol = 1e-7 * scale;
    double worst = 0.0;
    for (std::size_t i = 0; i < tr.t.size(); ++i) {
      double lost = 0.0;
      for (const auto& ev : r.events)
        if (ev.t < tr.t[i]) lost += ev.energy_lost;  // a step ending at an event ends before it
      const double bal = E(tr.q[i], tr.qd[i]) + lost - E0;  // in [-friction so far, 0]
      worst = std::max(worst, std::max(bal, -bal - friction));
    }
    BOOST_TEST(worst < tol, "worst excursion " << worst);
    const double end = E(tr.q.back(), tr.qd.back()) + impacts + friction - E0;
    BOOST_TEST(std::abs(end) < tol, "balance at the end " << end);
    BOOST_TEST_MESSAGE(c.name << ": E0 = " << E0 << " J, impacts " << impacts << " J, friction " << friction
                              << " J, balance at the end " << end << " J, " << r.events.size() << " events");
  }
}

Eigen::VectorXd v(std::initializer_list<double> x) {
  Eigen::VectorXd out(static_cast<int>(x.size()));
  int i = 0;
  for (double d : x) out[i++] = d;
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(bouncing_ball_loses_exactly_what_its_impacts_dissipate) {
  check_balance({"ball e = 0.5", "bouncing_ball", {{"e_n", 0.5}}, v({1.0}), v({0.0}), v({1.0}),
                 [](const Eigen::VectorXd& q) { return kG * q[0]; }, 3.0});
  check_balance({"ball e = 0.9", "bouncing_ball", {{"e_n", 0.9}}, v({0.3}), v({2.0}), v({1.0}),
                 [](const Eigen::VectorXd& q) { return kG * q[0]; }, 3.0});
}

BOOST_AUTO_TEST_CASE(block_loses_exactly_the_friction_work) {
  for (double alpha : {0.3, 0.5}) {
    const std::map<std::string, double> p = {{"alpha", alpha}, {"mu_s", 0.4}, {"mu_k", 0.3}};
    check_balance({"block alpha = " + std::to_string(alpha), "block_incline", p, v({0.0, 0.0}), v({-2.0, 0.0}),
                   v({2.0, 2.0}),
                   [alpha](const Eigen::VectorXd& q) { return 2.0 * kG * (q[1] * std::cos(alpha) - q[0] * std::sin(alpha)); },
                   1.5});
  }
}

BOOST_AUTO_TEST_CASE(disk_rolls_without_loss_and_slides_with_friction_work) {
  for (double alpha : {0.3, 0.8}) {
    const std::map<std::string, double> p = {{"alpha", alpha}, {"mu", 0.2}};
    check_balance({"disk alpha = " + std::to_string(alpha), "disk_incline", p, v({0.0, 0.2, 0.0}),
                   v({0.0, 0.0, 0.0}), v({1.5, 1.5, 0.03}),
                   [alpha](const Eigen::VectorXd& q) { return 1.5 * kG * (q[1] * std::cos(alpha) - q[0] * std::sin(alpha)); },
                   1.0});
  }
}

BOOST_AUTO_TEST_CASE(rocking_block_loses_exactly_what_its_impacts_dissipate) {
  const double b = 0.1, h = 0.3, th0 = 0.1;
  const std::map<std::string, double> p = {{"b", b}, {"h", h}, {"m", 10.0}, {"e_n", 0.0}, {"mu", 1.0}};
  check_balance({"rocking block", "rocking_block", p, v({0.0, b * std::sin(th0) + h * std::cos(th0), th0}),
                 v({0.0, 0.0, 0.0}), v({10.0, 10.0, 10.0 * (b * b + h * h) / 3}),
                 [](const Eigen::VectorXd& q) { return 10.0 * kG * q[1]; }, 1.5});
}
