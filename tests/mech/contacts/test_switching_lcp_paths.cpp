// The mode decisions of a single contact are solved in closed form (its four modes: open,
// stick, slide either way); with SwitchingOptions::lcp = always the same decisions go through
// the planar Coulomb LCP and Siconos. Both paths must give the same events, to rounding: this
// proves the closed form is the LCP's solution and the LCP assembly is right. (The rocking
// block, with two contacts, always takes the LCP: test_switching_rocking_block.)
#define BOOST_TEST_MODULE switching_lcp_paths
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "switching_util.hpp"

using namespace switching_test;

namespace {

void same_events(const std::string& stem, const std::map<std::string, double>& p, const Eigen::VectorXd& q0,
                 const Eigen::VectorXd& qd0, double t_end, double flight_hmax = 0.0) {
  auto m = contact_model(stem, p, q0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  SwitchingOptions closed, lcp;
  closed.flight_hmax = lcp.flight_hmax = flight_hmax;
  lcp.lcp = SwitchingOptions::Lcp::always;
  const auto a = run(*m, q0, qd0, t_end, o, closed);
  const auto b = run(*m, q0, qd0, t_end, o, lcp);
  BOOST_TEST_CONTEXT(stem) {
    BOOST_REQUIRE_MESSAGE(a.status == SimulationStatus::success, a.message);
    BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
    BOOST_TEST(a.lcp_solves == 0);
    BOOST_TEST(b.lcp_solves > 0);
    BOOST_REQUIRE_EQUAL(a.events.size(), b.events.size());
    for (std::size_t i = 0; i < a.events.size(); ++i) {
      const auto &x = a.events[i], &y = b.events[i];
      BOOST_TEST(x.kind == y.kind);
      BOOST_TEST(x.mode_after == y.mode_after);
      BOOST_TEST(std::abs(x.t - y.t) < 1e-12 * (1 + t_end));
      BOOST_TEST(std::abs(x.vn_after - y.vn_after) < 1e-10);
      BOOST_TEST(std::abs(x.vt_after - y.vt_after) < 1e-10);
      BOOST_TEST(std::abs(x.normal - y.normal) < 1e-9 * (1 + std::abs(x.normal)));
    }
    BOOST_TEST((a.q_end - b.q_end).cwiseAbs().maxCoeff() < 1e-9);
    BOOST_TEST_MESSAGE(stem << ": " << a.events.size() << " events agree; " << b.lcp_solves << " LCPs solved by Siconos");
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(closed_form_and_siconos_agree_on_single_contacts) {
  same_events("bouncing_ball", {{"e_n", 0.6}}, Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1), 2.0);
  same_events("block_incline", {{"alpha", 0.3}}, Eigen::Vector2d(0, 0), Eigen::Vector2d(-2, 0), 1.0);
  same_events("block_incline", {{"alpha", 0.5}}, Eigen::Vector2d(0, 0), Eigen::Vector2d(-2, 0), 1.0);
  same_events("disk_incline", {{"alpha", 0.8}}, Eigen::Vector3d(0, 0.2, 0), Eigen::Vector3d(0, 0, 0), 1.0);
  same_events("table_ball", {{"A", 0.002}, {"omega", 100.0}}, Eigen::VectorXd::Zero(1),
              Eigen::VectorXd::Constant(1, 0.2), 0.2, 2 * M_PI / 100.0 / 16);
}
