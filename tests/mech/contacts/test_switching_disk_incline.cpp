// A disk on an incline (models/contact/disk_incline.toml): it rolls when
// tan(alpha) <= mu (1 + m r^2 / J) and slides otherwise, from rest. On both sides of the
// closed-form threshold the accelerations are exact: rolling x_dd = g sin(alpha) / (1 + J/(m r^2)),
// phi_dd = -x_dd / r; sliding x_dd = g (sin(alpha) - mu cos(alpha)),
// phi_dd = -mu m g r cos(alpha) / J. Constant accelerations: the integrators are exact to
// rounding (tolerance 1e-10 relative); the threshold is resolved to 1e-7 in alpha.
#define BOOST_TEST_MODULE switching_disk_incline
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "switching_util.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kM = 1.5, kR = 0.2, kJ = 0.03, kMu = 0.2;

double threshold() { return std::atan(kMu * (1 + kM * kR * kR / kJ)); }

SwitchingResult roll_from_rest(double alpha, double T, Trace* tr) {
  const Eigen::Vector3d q0(0.0, kR, 0.0);
  auto m = contact_model("disk_incline", {{"alpha", alpha}, {"mu", kMu}}, q0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  return run(*m, q0, Eigen::Vector3d::Zero(), T, o, {}, tr);
}
}  // namespace

BOOST_AUTO_TEST_CASE(below_the_threshold_it_rolls_with_the_exact_acceleration) {
  const double T = 1.0;
  for (double alpha : {0.3, threshold() * (1 - 1e-7)}) {
    Trace tr;
    const auto r = roll_from_rest(alpha, T, &tr);
    BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
    const double a = kG * std::sin(alpha) / (1 + kJ / (kM * kR * kR));
    BOOST_TEST_CONTEXT("alpha = " << alpha) {
      BOOST_TEST(r.events.empty());
      BOOST_TEST(tr.modes.back()[0] == ContactMode::stick);
      BOOST_TEST(std::abs(r.q_end[0] - 0.5 * a * T * T) < 1e-10 * a);
      BOOST_TEST(std::abs(r.qd_end[0] - a * T) < 1e-10 * a);
      BOOST_TEST(std::abs(r.qd_end[2] + a * T / kR) < 1e-10 * a / kR);
      // The friction it needs stays inside the cone, mu m g cos(alpha).
      const double need = kM * (kG * std::sin(alpha) - a);
      BOOST_TEST(std::abs(-tr.R.back()[0] - need) < 1e-9 * need);
      BOOST_TEST(need <= kMu * kM * kG * std::cos(alpha) * (1 + 1e-9));
    }
  }
}

BOOST_AUTO_TEST_CASE(above_the_threshold_it_slides_with_the_exact_accelerations) {
  const double T = 1.0;
  for (double alpha : {threshold() * (1 + 1e-7), 0.8}) {
    Trace tr;
    const auto r = roll_from_rest(alpha, T, &tr);
    BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
    const double a = kG * (std::sin(alpha) - kMu * std::cos(alpha));
    const double b = -kMu * kM * kG * kR * std::cos(alpha) / kJ;
    BOOST_TEST_CONTEXT("alpha = " << alpha) {
      BOOST_TEST(r.events.empty());
      BOOST_TEST(tr.modes.back()[0] == ContactMode::slip);
      BOOST_TEST(std::abs(r.q_end[0] - 0.5 * a * T * T) < 1e-10 * a);
      BOOST_TEST(std::abs(r.qd_end[0] - a * T) < 1e-10 * a);
      BOOST_TEST(std::abs(r.qd_end[2] - b * T) < 1e-10 * std::abs(b));
    }
  }
}
