// A chain of 30 pendulum links in absolute coordinates (models/pendulum_chain_30.toml: 90
// coordinates, 60 holonomic joint constraints) runs through the engine and conserves its
// mechanical energy; the committed file is what its generator writes.
#define BOOST_TEST_MODULE modelfile_chain
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "chain_model.hpp"
#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

// A consistent state of an N-link chain: link i at angle th_i, centres placed link by link from
// the pivot, velocities from the angular rates w_i (so every joint constraint holds exactly).
void chain_state(int N, double L, const Eigen::VectorXd& th, const Eigen::VectorXd& w,
                 Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  q.resize(3 * N);
  qd.resize(3 * N);
  double px = 0, py = 0, vx = 0, vy = 0;  // the top end of the current link and its velocity
  for (int i = 0; i < N; ++i) {
    const double s = std::sin(th[i]), c = std::cos(th[i]), h = L / 2;
    q.segment(3 * i, 3) << px + h * s, py - h * c, th[i];
    qd.segment(3 * i, 3) << vx + h * c * w[i], vy + h * s * w[i], w[i];
    px += L * s;
    py -= L * c;
    vx += L * c * w[i];
    vy += L * s * w[i];
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(committed_chain_file_is_the_generators_output) {
  std::ifstream in(model_path("pendulum_chain_30.toml"));
  std::stringstream ss;
  ss << in.rdbuf();
  BOOST_TEST(ss.str() == pendulum_chain_toml(30));
}

// The chain starts from a bent, swinging shape and moves for 0.02 s (a short run: dense linear
// algebra on 90 coordinates is slow in the sanitized Debug build, about 30 s here;
// bench_modelfile_chain measures longer runs). The engine keeps the joints closed by
// projection; nothing else removes or adds energy, so the mechanical energy (the file's output
// "energy") stays at its initial value to the integration error: rtol = atol = 1e-8 gives drifts
// of order 1e-7 J here; the test allows 1e-6 of the energy scale m g L N^2 / 2 (the potential
// energy range of the chain, 44 J).
BOOST_AUTO_TEST_CASE(chain_of_30_links_conserves_energy) {
  const int N = 30;
  const double L = 0.1, m = 1.0, g = 9.81;
  const auto desc = load_model_file(model_path("pendulum_chain_30.toml"));
  BOOST_TEST(desc->n() == 3 * N);
  BOOST_TEST(desc->constraints().size() == 2u * N);
  const auto model = desc->instantiate({});
  Eigen::VectorXd th(N), w(N), q, qd;
  for (int i = 0; i < N; ++i) {
    th[i] = 0.8 * std::sin(0.2 * i) + 0.3;
    w[i] = 3.0 * std::cos(0.3 * i);
  }
  chain_state(N, L, th, w, q, qd);
  mech::SimulationOptions o;
  o.t_end = 0.02;
  o.rtol = o.atol = 1e-8;
  o.kernel = Kernel::fortran;  // in Debug builds 4x faster than the sanitized C++ Huang port
  o.active_constraints = desc->default_active_constraints();
  double e0 = NAN, drift = 0.0;
  const mech::SimulationResult r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample s = v.at(v.t);
    if (std::isnan(e0)) e0 = s.derived[0];
    drift = std::max(drift, std::abs(s.derived[0] - e0));
    return true;
  });
  BOOST_TEST_MESSAGE("chain N = 30: " << r.stats.steps << " steps, " << r.stats.f_evals
                     << " f-evaluations, energy " << e0 << " J, max drift " << drift
                     << " J, max joint residual " << r.residual_pos_max);
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST(r.initial_correction_pos < 1e-12);  // the start was consistent
  BOOST_TEST(r.initial_correction_vel < 1e-12);
  const double scale = m * g * L * N * N / 2;
  BOOST_TEST(drift < 1e-6 * scale);
  BOOST_TEST(r.residual_pos_max < 1e-10);
  // It moved: the links turned by up to w t = 0.06 rad.
  BOOST_TEST((r.q_end - q).cwiseAbs().maxCoeff() > 0.02);
}
