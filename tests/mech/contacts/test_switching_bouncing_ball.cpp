// A ball dropped on a fixed floor (models/contact/bouncing_ball.toml) against the exact
// solution: landing at t1 = sqrt(2H/g) with v1 = g t1, rebounds e^k v1, flights 2 e^k v1 / g,
// apexes e^(2k) H, and for e < 1 rest at the accumulation time t1 + 2 e v1 / (g (1 - e)),
// after which the contact holds. The free flight is a parabola, which every Runge-Kutta
// method integrates exactly, so the only errors are the event location (100 eps |t|) and
// rounding: the tolerances below are 1e-10 relative over a dozen bounces.
#define BOOST_TEST_MODULE switching_bouncing_ball
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <fstream>
#include <string>

#include "switching_util.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kH = 1.0;
}

BOOST_AUTO_TEST_CASE(impact_times_speeds_and_apexes_follow_the_geometric_series) {
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    for (OdeMethod method : {OdeMethod::radau, OdeMethod::explicit_rk}) {
      for (double e : {0.5, 0.8}) {
        auto m = contact_model("bouncing_ball", {{"e_n", e}});
        SimulationOptions o;
        o.kernel = k;
        o.method = method;
        o.rtol = o.atol = 1e-10;
        SwitchingOptions sw;
        sw.zeno_time = 1e-9;
        const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 5.0, o, sw);
        BOOST_TEST_CONTEXT(to_string(k) << " " << to_string(method) << " e = " << e) {
          BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
          const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
          const auto impacts = events_of(r, ContactEventKind::impact);
          BOOST_REQUIRE(impacts.size() >= 10u);
          double t_exact = t1, v = v1;
          for (std::size_t i = 0; i < 10; ++i) {
            BOOST_TEST(std::abs(impacts[i].t - t_exact) < 1e-10 * t_exact, "impact " << i << " at " << impacts[i].t << " exact " << t_exact);
            BOOST_TEST(std::abs(-impacts[i].vn_before - v) < 1e-9 * v1);
            BOOST_TEST(std::abs(impacts[i].vn_after - e * v) < 1e-9 * v1);
            BOOST_TEST(std::abs(impacts[i].normal - (1 + e) * v) < 1e-9 * v1);  // impulse m (1 + e) v, m = 1
            BOOST_TEST(std::abs(impacts[i].energy_lost - 0.5 * (1 - e * e) * v * v) < 1e-9 * v1 * v1);
            t_exact += 2 * e * v / kG;
            v *= e;
          }
          // Apexes of the flights after each impact: e^(2k) H.
          const auto& fl = r.contacts.at(0).flights;
          BOOST_REQUIRE(fl.size() >= 10u);
          double apex = kH;
          for (std::size_t i = 1; i < 10; ++i) {
            apex *= e * e;
            BOOST_TEST(std::abs(fl[i].max_gap - apex) < 1e-9 * kH, "flight " << i << " apex " << fl[i].max_gap << " exact " << apex);
          }
        }
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(with_restitution_below_one_it_rests_at_the_accumulation_time) {
  const double e = 0.5;
  auto m = contact_model("bouncing_ball", {{"e_n", e}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  SwitchingOptions sw;
  sw.zeno_time = 1e-8;
  Trace tr;
  const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 4.0, o, sw, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
  const double t_inf = t1 + 2 * e * v1 / (kG * (1 - e));
  const auto acc = events_of(r, ContactEventKind::accumulation);
  BOOST_REQUIRE_EQUAL(acc.size(), 1u);
  // The rule closes the contact at the last impact whose rebound would fly less than zeno_time;
  // the bounces it skips would have lasted at most zeno_time / (1 - e).
  BOOST_TEST_MESSAGE("accumulation closed at t = " << acc[0].t << ", exact t_inf = " << t_inf << ", after "
                                                   << events_of(r, ContactEventKind::impact).size() << " impacts");
  BOOST_TEST(acc[0].t <= t_inf + 1e-10);
  BOOST_TEST(t_inf - acc[0].t <= sw.zeno_time / (1 - e) + 1e-10);
  BOOST_TEST(acc[0].vn_after == 0.0);
  BOOST_TEST(acc[0].mode_after == ContactMode::contact);
  BOOST_TEST(r.events.back().t == acc[0].t);  // nothing happens afterwards
  // The contact holds to the end: at rest on the floor, carrying the weight m g.
  BOOST_TEST(std::abs(r.q_end[0]) < 1e-12);
  BOOST_TEST(std::abs(r.qd_end[0]) < 1e-12);
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.t[i] <= acc[0].t) continue;
    BOOST_TEST(tr.modes[i][0] == ContactMode::contact);
    BOOST_TEST(std::abs(tr.R[i][0] - kG) < 1e-9);
  }
  // Closed from the accumulation to the end.
  BOOST_TEST(std::abs(r.contacts[0].run.closed_time - (4.0 - acc[0].t)) < 1e-9);
}

BOOST_AUTO_TEST_CASE(an_elastic_ball_bounces_with_period_2_t1_forever) {
  auto m = contact_model("bouncing_ball", {{"e_n", 1.0}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 10.0, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double t1 = std::sqrt(2 * kH / kG);
  const auto impacts = events_of(r, ContactEventKind::impact);
  BOOST_REQUIRE_EQUAL(impacts.size(), static_cast<std::size_t>(std::floor((10.0 - t1) / (2 * t1)) + 1));
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    BOOST_TEST(std::abs(impacts[i].t - (2 * i + 1) * t1) < 1e-10 * 10.0);
    BOOST_TEST(std::abs(impacts[i].energy_lost) < 1e-9);
  }
  BOOST_TEST(events_of(r, ContactEventKind::accumulation).empty());
  BOOST_TEST(r.contacts[0].run.max_flight_height <= kH * (1 + 1e-10));
  BOOST_TEST(r.contacts[0].run.max_flight_height >= kH * (1 - 1e-10));
}

// A single contact's complementarity problem is solved in closed form: none of the runs above
// loads the LCP plugin, hence neither Siconos nor the OpenBLAS it links.
BOOST_AUTO_TEST_CASE(single_contact_runs_never_load_siconos_or_openblas) {
  BOOST_TEST(!lcp::lcp_library_loaded());
  std::ifstream maps("/proc/self/maps");
  std::string line;
  bool siconos = false, openblas = false;
  while (std::getline(maps, line)) {
    siconos = siconos || line.find("siconos") != std::string::npos;
    openblas = openblas || line.find("openblas") != std::string::npos;
  }
  BOOST_TEST(!siconos);
  BOOST_TEST(!openblas);
}
