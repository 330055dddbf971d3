// The Whipple bicycle written as bodies and joints (models/whipple_bodies.toml: a spatial rear
// frame in Euler parameters, fork and wheels on revolute tree joints, two wheels rolling without
// slip; 10 coordinates, 3 holonomic and 4 velocity-form rows), linearized by pcsim modes about
// straight-ahead running (rear_x and the wheel angles cyclic), against the published benchmark
// (Meijaard, Papadopoulos, Ruina, Schwab 2007, Proc. R. Soc. A 463): the eigenvalues of
// M q_dd + v C1 q_d + (g K0 + v^2 K2) q = 0 with the paper's matrices (the same published numbers
// as test_modes_whipple, which checks the hand-derived energy-form model).
#define BOOST_TEST_MODULE modes_whipple_bodies
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

std::vector<std::complex<double>> nonzero(const nlohmann::json& j) {
  std::vector<std::complex<double>> out;
  for (const auto& e : j["eigenvalues"]) {
    const std::complex<double> l(e["re"].get<double>(), e["im"].get<double>());
    if (std::abs(l) > 1e-3) out.push_back(l);
  }
  return out;
}

}  // namespace

// v = 1, 3, 4.6, 6, 8 m/s (both sides of the weave and capsize speeds): the four nonzero
// eigenvalues equal the benchmark's to 1e-8 (the published matrices' 14 digits allow ~1e-10).
BOOST_AUTO_TEST_CASE(whipple_bodies_eigenvalues_match_the_benchmark) {
  const auto t0 = std::chrono::steady_clock::now();
  const sim::Case base = sim::load_case("tests/modes/whipple/whipple_bodies_case.toml");
  const double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  BOOST_TEST_MESSAGE("Whipple bicycle as bodies: case and model loaded (expanded, derived, compiled) in " << load << " s");
  double worst = 0;
  for (double v : {1.0, 3.0, 4.6, 6.0, 8.0}) {
    sim::Case c = base;
    auto& init = *c.table["initial"].as_table();
    init.insert_or_assign("rear_x_d", v);
    init.insert_or_assign("thR_d", -v / 0.3);
    init.insert_or_assign("thF_d", -v / 0.35);
    sim::retype(c);
    const nlohmann::json j = case_modes(c, {});
    BOOST_TEST(j["reference"]["kind"].get<std::string>() == "steady motion");
    const auto got = nonzero(j);
    BOOST_TEST_REQUIRE(got.size() == 4u, "v = " << v << ": " << got.size() << " nonzero eigenvalues");
    const double d = set_distance(got, benchmark(v));
    worst = std::max(worst, d);
    BOOST_TEST(d <= 1e-8, "v = " << v << ": distance " << d);
  }
  BOOST_TEST_MESSAGE("largest distance to the benchmark's eigenvalues: " << worst);
}
