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

// ---- The same disk written with bodies and joints (issue 22): a `rolling` joint whose rows carry
// the contact attributes (models/contact/disk_incline_bodies.toml). Its coordinates are the
// disk's ground position and angle; s = x cos(alpha) - y sin(alpha) is the travel down the slope.
// Oracles: the closed forms above, and the energy-form model of this file run alongside.
namespace {

struct BodyDisk {
  SwitchingResult r;
  Trace tr;
  double s_end = 0, v_end = 0;  ///< travel and speed down the slope at the end
};

BodyDisk body_disk(double alpha, double mu_s, double mu_k, double w0, double T, double X0 = 0.0,
                   double Y0 = 0.0) {
  const Eigen::Vector3d q0(X0 + kR * std::sin(alpha), Y0 + kR * std::cos(alpha), 0.0);
  auto m = contact_model("disk_incline_bodies",
                         {{"alpha", alpha}, {"mu_s", mu_s}, {"mu_k", mu_k}, {"X0", X0}, {"Y0", Y0}}, q0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  BodyDisk d;
  d.r = run(*m, q0, Eigen::Vector3d(0.0, 0.0, w0), T, o, {}, &d.tr);
  d.s_end = (d.r.q_end[0] - q0[0]) * std::cos(alpha) - (d.r.q_end[1] - q0[1]) * std::sin(alpha);
  d.v_end = d.r.qd_end[0] * std::cos(alpha) - d.r.qd_end[1] * std::sin(alpha);
  return d;
}

}  // namespace

BOOST_AUTO_TEST_CASE(disk_as_a_body_on_a_rolling_joint_rolls_below_the_friction_limit) {
  const double T = 1.0;
  for (double alpha : {0.3, threshold() * (1 - 1e-7)}) {
    const BodyDisk d = body_disk(alpha, kMu, kMu, 0.0, T);
    BOOST_REQUIRE_MESSAGE(d.r.status == SimulationStatus::success, d.r.message);
    const double a = kG * std::sin(alpha) / (1 + kJ / (kM * kR * kR));
    BOOST_TEST_CONTEXT("alpha = " << alpha) {
      BOOST_TEST(d.r.events.empty());
      BOOST_TEST(d.tr.modes.back()[0] == ContactMode::stick);
      BOOST_TEST(std::abs(d.s_end - 0.5 * a * T * T) < 1e-10 * a);
      BOOST_TEST(std::abs(d.v_end - a * T) < 1e-10 * a);
      BOOST_TEST(std::abs(d.r.qd_end[2] + a * T / kR) < 1e-10 * a / kR);
    }
  }
}

// Above the limit it slides with the kinetic coefficient (mu_k < mu_s here: the static one
// decides that it slides, the kinetic one how fast), the friction torque spinning it up.
BOOST_AUTO_TEST_CASE(disk_as_a_body_slides_above_the_friction_limit_with_mu_kinetic) {
  const double T = 1.0, mu_k = 0.15;
  for (double alpha : {threshold() * (1 + 1e-7), 0.8}) {
    const BodyDisk d = body_disk(alpha, kMu, mu_k, 0.0, T);
    BOOST_REQUIRE_MESSAGE(d.r.status == SimulationStatus::success, d.r.message);
    const double a = kG * (std::sin(alpha) - mu_k * std::cos(alpha));
    const double b = -mu_k * kM * kG * kR * std::cos(alpha) / kJ;
    BOOST_TEST_CONTEXT("alpha = " << alpha) {
      BOOST_TEST(d.r.events.empty());
      BOOST_TEST(d.tr.modes.back()[0] == ContactMode::slip);
      BOOST_TEST(std::abs(d.s_end - 0.5 * a * T * T) < 1e-10 * a);
      BOOST_TEST(std::abs(d.v_end - a * T) < 1e-10 * a);
      BOOST_TEST(std::abs(d.r.qd_end[2] - b * T) < 1e-10 * std::abs(b));
      // The rolling joint's reaction in its frame: friction -mu_k N along the slope, N normal.
      const double N = kM * kG * std::cos(alpha);
      BOOST_TEST(std::abs(d.tr.R.back()[0] * std::cos(alpha) - d.tr.R.back()[1] * std::sin(alpha) + mu_k * N) < 1e-9 * N);
    }
  }
}

// The switch: spun backwards (the contact point sliding up the slope at r |w0|) the disk slides,
// friction (down the slope) speeding its centre and braking its spin, until the sliding velocity
// is 0 at t* = r |w0| / (g sin(alpha) + mu_k g cos(alpha) (1 + m r^2 / J)); then it rolls. The
// energy-form disk (disk_incline.toml, a holonomic friction row) switches at the same instant.
BOOST_AUTO_TEST_CASE(disk_as_a_body_spun_backwards_sticks_at_the_closed_form_instant_as_the_energy_form) {
  const double alpha = 0.5, w0 = -10.0, T = 0.6;
  const double ts = kR * -w0 / (kG * std::sin(alpha) + kMu * kG * std::cos(alpha) * (1 + kM * kR * kR / kJ));
  const BodyDisk d = body_disk(alpha, kMu, kMu, w0, T);
  BOOST_REQUIRE_MESSAGE(d.r.status == SimulationStatus::success, d.r.message);
  BOOST_REQUIRE_EQUAL(d.r.events.size(), 1u);
  BOOST_TEST(d.r.events[0].kind == ContactEventKind::stick);
  BOOST_TEST(std::abs(d.r.events[0].t - ts) < 1e-10, "stick at " << d.r.events[0].t << ", exact " << ts);
  // Then rolling: the speed at t* (slip acceleration g (sin + mu_k cos)) plus rolling's.
  const double a_slip = kG * (std::sin(alpha) + kMu * std::cos(alpha));
  const double a_roll = kG * std::sin(alpha) / (1 + kJ / (kM * kR * kR));
  BOOST_TEST(std::abs(d.v_end - (a_slip * ts + a_roll * (T - ts))) < 1e-9);
  BOOST_TEST(std::abs(d.r.qd_end[2] + d.v_end / kR) < 1e-9);
  // The energy form, same initial state (x, y, phi) = (0, r, 0), phi_d = w0.
  const Eigen::Vector3d q0(0.0, kR, 0.0);
  auto m = contact_model("disk_incline", {{"alpha", alpha}, {"mu", kMu}}, q0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto e = run(*m, q0, Eigen::Vector3d(0.0, 0.0, w0), T, o);
  BOOST_REQUIRE_MESSAGE(e.status == SimulationStatus::success, e.message);
  BOOST_REQUIRE_EQUAL(e.events.size(), 1u);
  BOOST_TEST(e.events[0].kind == d.r.events[0].kind);
  BOOST_TEST(std::abs(e.events[0].t - d.r.events[0].t) < 1e-10);
  BOOST_TEST(std::abs(e.events[0].normal - d.r.events[0].normal) < 1e-9);
  BOOST_TEST(std::abs(e.qd_end[0] - d.v_end) < 1e-9);
  BOOST_TEST(std::abs(e.qd_end[2] - d.r.qd_end[2]) < 1e-9);
}
