// Steady motions ([modes] cyclic): the conical pendulum (a spherical pendulum precessing at the
// rate W with W^2 = g/(L cos th0)) linearized about its relative equilibrium: the cyclic angle
// gives a zero mode labelled cyclic, and the nutation oscillates at W sqrt(1 + 3 cos^2 th0)
// (from the reduced equation d2(dth)/dt2 = -W^2 (1 + 3 cos^2 th0) dth, derived by hand in the
// model file's comment); a wrong rate is refused with the residual and the coordinate that
// accelerates, and a "cyclic" coordinate that appears in the equations is refused.
#define BOOST_TEST_MODULE modes_steady_motion
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../support/cli_util.hpp"
#include "common/error.hpp"
#include "modes/modes_case.hpp"
#include "sim/case.hpp"

using namespace pcsim;
using namespace pcsim::modes;

namespace {

constexpr double kTh0 = 0.6, kL = 0.8, kG = 9.81;

sim::Case conical(double rate, const std::string& cyclic = "ph") {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "model = \"tests/modes/spherical_pendulum.toml\"\n[initial]\nth = %.17g\nph_d = %.17g\n"
                "[modes]\ncyclic = [\"%s\"]\n",
                kTh0, rate, cyclic.c_str());
  return sim::load_case_text(buf, "conical.toml");
}

double rate() { return std::sqrt(kG / (kL * std::cos(kTh0))); }

}  // namespace

BOOST_AUTO_TEST_CASE(conical_pendulum_nutation_frequency_and_cyclic_mode) {
  const double W = rate();
  const nlohmann::json j = case_modes(conical(W), {});
  BOOST_TEST(j["reference"]["kind"].get<std::string>() == "steady motion");
  BOOST_TEST(j["tangent_space"]["dimension"].get<int>() == 4);
  const double want = W * std::sqrt(1 + 3 * std::cos(kTh0) * std::cos(kTh0));
  int osc = 0, cyc = 0;
  for (const auto& m : j["modes"]) {
    if (m["kind"] == "oscillatory") {
      ++osc;
      // 1e-12: the linearization is exact (symbolic tangents); rounding only.
      BOOST_TEST(std::abs(m["im"].get<double>() - want) <= 1e-12 * want);
      BOOST_TEST(std::abs(m["re"].get<double>()) <= 1e-12 * want);
    }
    if (m["kind"] == "cyclic") ++cyc;
  }
  BOOST_TEST(osc == 1);
  BOOST_TEST(cyc >= 1);  // the shift of ph (and the change of the rate: a Jordan block at 0)
  BOOST_TEST(j["zero_modes"].get<int>() >= 1);
}

BOOST_AUTO_TEST_CASE(a_rate_that_is_not_steady_is_refused_naming_the_coordinate) {
  try {
    case_modes(conical(1.1 * rate()), {});
    BOOST_FAIL("expected InputError");
  } catch (const InputError& e) {
    BOOST_TEST_MESSAGE(e.what());
    BOOST_TEST(pcsim_test::has(e.what(), "not a steady motion"));
    BOOST_TEST(pcsim_test::has(e.what(), "accelerating: th"));
  }
}

BOOST_AUTO_TEST_CASE(a_cyclic_coordinate_in_the_equations_is_refused) {
  // th appears in T and V: not cyclic (and th_d = 0 while ph_d != 0: ph must be cyclic too).
  sim::Case c = conical(rate(), "th");
  try {
    case_modes(c, {});
    BOOST_FAIL("expected InputError");
  } catch (const InputError& e) {
    BOOST_TEST_MESSAGE(e.what());
    BOOST_TEST(pcsim_test::has(e.what(), "cyclic coordinate(s) th appear in the equations"));
  }
  // Without any cyclic coordinate the precessing state is no rest state: ph moves.
  ModesOptions o;
  o.cyclic = std::vector<std::string>{};
  BOOST_CHECK_EXCEPTION(case_modes(conical(rate()), o), InputError,
                        [](const InputError& e) { return pcsim_test::has(e.what(), "q_d = 0, but ph move"); });
  // An unknown name.
  o.cyclic = std::vector<std::string>{"psi"};
  BOOST_CHECK_EXCEPTION(case_modes(conical(rate()), o), InputError,
                        [](const InputError& e) { return pcsim_test::has(e.what(), "modes.cyclic"); });
}
