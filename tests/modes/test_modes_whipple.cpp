// The Whipple bicycle (Meijaard, Papadopoulos, Ruina, Schwab 2007, Proc. R. Soc. A 463): the
// nonlinear model file tests/modes/whipple/ (8 coordinates, the front contact holonomic, four
// no-slip velocity rows; written by make_whipple_model.py from the bodies' energies), linearized
// by pcsim modes about straight-ahead running, against the paper's linearized benchmark: the
// eigenvalues of M q_dd + v C1 q_d + (g K0 + v^2 K2) q = 0 with the paper's published matrices
// (its Appendix; Table 2 lists these eigenvalues), for v = 0 .. 10 m/s, and the weave and
// capsize speeds 4.29238253634111 and 6.02426201538837 m/s found by --vary's root-finder. The
// published numbers below were typed in from the paper (recalled, not copied from a file); their
// agreement with the nonlinear model to 6e-10 and 2e-15 is itself the check on the typing.
#define BOOST_TEST_MODULE modes_whipple
#include <boost/test/unit_test.hpp>

#include <chrono>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "modes/modes_case.hpp"
#include "modes_test_util.hpp"
#include "sim/case.hpp"

using namespace pcsim;
using namespace pcsim::modes;
using namespace pcsim::modes::testing;

namespace {

// The benchmark's linearized equations (roll phi, steer delta), as published.
std::vector<std::complex<double>> benchmark(double v) {
  Eigen::Matrix2d M, C1, K0, K2;
  M << 80.81722, 2.31941332208709, 2.31941332208709, 0.29784188199686;
  C1 << 0, 33.86641391492494, -0.85035641456978, 1.68540397397560;
  K0 << -80.95, -2.59951685249872, -2.59951685249872, -0.80329488458618;
  K2 << 0, 76.59734589573222, 0, 2.65431523794604;
  const double g = 9.81;
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  A.topRightCorner(2, 2).setIdentity();
  A.bottomLeftCorner(2, 2) = -M.inverse() * (g * K0 + v * v * K2);
  A.bottomRightCorner(2, 2) = -M.inverse() * (v * C1);
  const Eigen::Vector4cd l = Eigen::EigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(A)).eigenvalues();
  return {l[0], l[1], l[2], l[3]};
}

// The eigenvalues of the reduced linearization that are not zero: the bicycle's x, y, yaw,
// wheel angles and speed give six zero eigenvalues (ignorable coordinates, a conserved speed).
std::vector<std::complex<double>> nonzero(const nlohmann::json& j) {
  std::vector<std::complex<double>> out;
  for (const auto& e : j["eigenvalues"]) {
    const std::complex<double> l(e["re"].get<double>(), e["im"].get<double>());
    if (std::abs(l) > 1e-3) out.push_back(l);
  }
  return out;
}

}  // namespace

// 1e-8 (the issue's): the model file is the nonlinear bicycle, the benchmark matrices are the
// paper's 14-digit numbers; measured: 6e-10 at worst over the table (the matrices' 14 digits).
BOOST_AUTO_TEST_CASE(eigenvalues_against_speed_match_the_benchmark) {
  const sim::Case base = sim::load_case("tests/modes/whipple/whipple_moving_case.toml");
  double worst = 0;
  for (int v = 0; v <= 10; ++v) {
    sim::Case c = base;  // the model derived once: the speed set in place
    c.table["parameters"].as_table()->insert_or_assign("v", static_cast<double>(v));
    sim::retype(c);
    const nlohmann::json j = case_modes(c, {});
    BOOST_TEST(j["tangent_space"]["dimension"].get<int>() == 10);
    const auto got = nonzero(j);
    const auto want = benchmark(v);
    BOOST_TEST_REQUIRE(got.size() == 4u, "v = " << v);
    const double d = set_distance(got, want);
    worst = std::max(worst, d);
    BOOST_TEST(d <= 1e-8, "v = " << v << ": distance " << d);
  }
  BOOST_TEST_MESSAGE("largest distance to the benchmark's eigenvalues over v = 0..10: " << worst);
}

// The straight-ahead motion at 4 m/s as a steady motion of the bicycle in its own coordinates
// (x and the wheel angles cyclic) gives the same eigenvalues.
BOOST_AUTO_TEST_CASE(steady_motion_with_cyclic_coordinates_gives_the_same_eigenvalues) {
  const sim::Case c = sim::load_case("tests/modes/whipple/whipple_case.toml");
  const nlohmann::json j = case_modes(c, {});
  BOOST_TEST(j["reference"]["kind"].get<std::string>() == "steady motion");
  BOOST_TEST(set_distance(nonzero(j), benchmark(4.0)) <= 1e-8);
  int cyclic = 0;
  for (const auto& m : j["modes"]) cyclic += m["kind"] == "cyclic";
  BOOST_TEST(cyclic >= 2);
}

// The weave speed (the weave pair's real part crosses 0) and the capsize speed (the capsize
// eigenvalue crosses 0 through the cluster of zero eigenvalues), from a trace over v with the
// root-finder on the real parts. The benchmark prints the wall time of the whole table.
BOOST_AUTO_TEST_CASE(weave_and_capsize_speeds_by_vary) {
  const sim::Case c = sim::load_case("tests/modes/whipple/whipple_moving_case.toml");
  const auto t0 = std::chrono::steady_clock::now();
  const nlohmann::json j = modes_vary(c, {}, parse_vary("parameters.v=0:10:11"));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  BOOST_TEST_MESSAGE("the table v = 0..10 m/s (11 linearizations) and the two speeds: " << wall << " s wall");
  double weave = NAN, capsize = NAN;
  for (const auto& x : j["stability_crossings"]) {
    if (x["direction"] == "becomes stable" && std::abs(x["im"].get<double>()) > 1) weave = x["value"].get<double>();
    if (x["direction"] == "becomes unstable" && std::abs(x["im"].get<double>()) < 1e-3) capsize = x["value"].get<double>();
  }
  BOOST_TEST(std::abs(weave - 4.29238253634111) <= 1e-10);
  BOOST_TEST(std::abs(capsize - 6.02426201538837) <= 1e-10);
}
