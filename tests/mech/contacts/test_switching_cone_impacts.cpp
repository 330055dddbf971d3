// Impacts with 2-D Coulomb cones never create energy (issue 19's property, for issue 22's cone):
// a generated family of impact configurations of a spatial rigid body, a tetrahedron of four
// particles of random masses held by six rods, whose first 1 to 3 vertices touch random planes,
// each contact with a random e_n in [0, 1] (1 in a seventh), and a 2-D cone (two friction rows
// along orthonormal tangents of its plane, velocity form) with mu in [0, 1] on most, hit with
// random velocities. The impact map (resolve_impact, the run's own: Newton's law, the cones'
// law contact by contact, the energy rule, the accumulation rule) never increases
// T = ½ Σ m_i |v_i|² beyond rounding, leaves no touching contact approaching, and keeps each
// tangential impulse in its cone. The oracle is T and the velocities computed here.
//
// Every generated impact is resolved, the wedged ones too: three planes that squeeze the
// tetrahedron pose up to nine rows on its six velocities, forces that squeeze it without moving
// it are undetermined, and there Gauss-Seidel's forces drift without settling (ten resolutions
// were refused before) or settle short of a solution (one more, accepted before with its laws
// violated by 3.5e-3). Those go to the fallback on all contacts' laws at once (lcp_problem.cpp:
// Levenberg-Marquardt steps on the Alart-Curnier equations, De Saxcé's fixed point), which solves
// Newton's law with the cones in all but two wedged impacts (each resolved twice, with and without
// zeno_time); there none is found and the impact is the plastic one (impact.cpp), flagged as
// limited. The squeeze is not determined, so the laws are checked, not an impulse: Newton's law
// at every contact with an impulse (v_n⁺ = −e v_n⁻), and a contact that slides after the impulse
// on its cone's boundary.
#define BOOST_TEST_MODULE switching_cone_impacts
#include <boost/test/unit_test.hpp>

#include <chrono>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "switching_util.hpp"

using namespace switching_test;

namespace {

std::string tetrahedron_text() {
  std::ostringstream os;
  os << "[model]\nname = \"tetrahedron_on_planes\"\ncoordinates = [";
  for (int i = 1; i <= 4; ++i)
    for (const char* c : {"x", "y", "z"}) os << (i == 1 && std::string(c) == "x" ? "" : ", ") << '"' << c << i << '"';
  os << "]\n\n[model.parameters]\ng = { value = 9.81, unit = \"m/s^2\", meaning = \"gravity\" }\n";
  for (int i = 1; i <= 4; ++i) os << "m" << i << " = { value = 1.0, unit = \"kg\", meaning = \"mass\", positive = true }\n";
  for (int k = 1; k <= 3; ++k) {
    for (const char* p : {"nx", "ny", "nz", "ax", "ay", "az", "bx", "by", "bz", "d"})
      os << p << k << " = { value = 0.0, unit = \"1\", meaning = \"contact geometry\" }\n";
    os << "e" << k << " = { value = 0.5, unit = \"1\", meaning = \"restitution\", min = 0.0, max = 1.0 }\n";
    os << "mu" << k << " = { value = 0.5, unit = \"1\", meaning = \"friction\", min = 0.0 }\n";
  }
  os << "\n[model.energy]\nkinetic = \"";
  for (int i = 1; i <= 4; ++i)
    os << (i > 1 ? " + " : "") << "0.5*m" << i << "*(x" << i << "_d^2 + y" << i << "_d^2 + z" << i << "_d^2)";
  os << "\"\npotential = \"g*(m1*z1 + m2*z2 + m3*z3 + m4*z4)\"\n";
  for (int i = 1; i <= 4; ++i)
    for (int j = i + 1; j <= 4; ++j)
      os << "\n[[model.constraint]]\nname = \"rod" << i << j << "\"\nholonomic = \"(x" << j << " - x" << i << ")^2 + (y" << j
         << " - y" << i << ")^2 + (z" << j << " - z" << i << ")^2\"\nfrom_initial = true\n";
  for (int k = 1; k <= 3; ++k) {
    const std::string K = std::to_string(k);
    os << "\n[[model.constraint]]\nname = \"c" << K << "\"\nholonomic = \"nx" << K << "*x" << K << " + ny" << K << "*y" << K
       << " + nz" << K << "*z" << K << " - d" << K << "\"\nunilateral = true\nrestitution = \"e" << K << "\"\n";
    for (const char* t : {"a", "b"})
      os << "\n[[model.constraint]]\nname = \"f" << K << t << "\"\nvelocity = { x" << K << " = \"" << t << "x" << K
         << "\", y" << K << " = \"" << t << "y" << K << "\", z" << K << " = \"" << t << "z" << K << "\" }\nfriction = \"c"
         << K << "\"\nmu_static = \"mu" << K << "\"\n";
  }
  os << "\n[model.outputs]\nN1 = \"lambda_c1\"\nN2 = \"lambda_c2\"\nN3 = \"lambda_c3\"\n";  // normal forces
  return os.str();
}

}  // namespace

BOOST_AUTO_TEST_CASE(impacts_with_2d_cones_never_create_energy_nor_leave_a_contact_approaching) {
  const auto desc = modelfile::load_model_text(tetrahedron_text(), "tetrahedron_on_planes.toml");
  std::mt19937 rng(2211);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto unit = [&]() {
    Eigen::Vector3d v;
    do v = Eigen::Vector3d(2 * U(rng) - 1, 2 * U(rng) - 1, 2 * U(rng) - 1);
    while (v.norm() < 0.2 || v.norm() > 1.0);
    return Eigen::Vector3d(v.normalized());
  };
  long trials = 0, refused = 0, impacts = 0, several = 0, limited = 0, cones = 0;
  long refused_by[4] = {0, 0, 0, 0};
  long sweeps = 0, fallbacks = 0, unsolved = 0, newton_steps = 0, newton_checked = 0, slide_checked = 0;
  const auto clock_start = std::chrono::steady_clock::now();
  double worst_gain = -1.0;
  for (int trial = 0; trial < 600; ++trial) {
    const int nc = 1 + trial % 3;
    std::map<std::string, double> p;
    Eigen::VectorXd q(12), qd(12);
    Eigen::Vector4d mass;
    const Eigen::Vector3d centre(300.0 * (2 * U(rng) - 1), 300.0 * (2 * U(rng) - 1), 50.0 * U(rng));
    for (int i = 0; i < 4; ++i) {
      q.segment<3>(3 * i) = centre + 0.5 * Eigen::Vector3d(2 * U(rng) - 1, 2 * U(rng) - 1, 2 * U(rng) - 1);
      mass[i] = 0.2 + 2 * U(rng);
      p["m" + std::to_string(i + 1)] = mass[i];
    }
    std::vector<std::string> active{"rod12", "rod13", "rod14", "rod23", "rod24", "rod34"};
    std::vector<Eigen::Vector3d> normals;
    std::vector<bool> with_cone;
    for (int k = 1; k <= nc; ++k) {
      const std::string K = std::to_string(k);
      const Eigen::Vector3d n = unit();
      Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
      const double turn = 2 * M_PI * U(rng);  // the tangents turned about n
      const Eigen::Vector3d a2 = std::cos(turn) * a + std::sin(turn) * b, b2 = n.cross(a2);
      const char* c = "xyz";
      for (int j = 0; j < 3; ++j) {
        p[std::string("n") + c[j] + K] = n[j];
        p[std::string("a") + c[j] + K] = a2[j];
        p[std::string("b") + c[j] + K] = b2[j];
      }
      p["d" + K] = n.dot(q.segment<3>(3 * (k - 1)));  // touching at q
      p["e" + K] = trial % 7 == 0 ? 1.0 : U(rng);
      p["mu" + K] = U(rng);
      active.push_back("c" + K);
      with_cone.push_back(U(rng) < 0.8);
      if (with_cone.back()) {
        active.push_back("f" + K + "a");
        active.push_back("f" + K + "b");
        ++cones;
      }
      normals.push_back(n);
    }
    // A rigid velocity v_c + w x (p - c), so that the rods hold.
    const Eigen::Vector3d vc(2 * U(rng) - 1, 2 * U(rng) - 1, 2 * U(rng) - 1), w(4 * U(rng) - 2, 4 * U(rng) - 2, 4 * U(rng) - 2);
    for (int i = 0; i < 4; ++i) qd.segment<3>(3 * i) = vc + w.cross(q.segment<3>(3 * i) - centre);
    auto approaching = [&](const Eigen::VectorXd& v) {
      bool any = false;
      for (int k = 0; k < nc; ++k) any = any || normals[k].dot(v.segment<3>(3 * k)) < -1e-3;
      return any;
    };
    if (!approaching(qd)) qd = -qd;
    if (!approaching(qd)) continue;
    std::shared_ptr<const Model> model;
    try {
      model = desc->instantiate(p, q, 0.0);
    } catch (const std::exception& e) {
      BOOST_FAIL("instantiate: " << e.what());
    }
    for (double zeno : {0.0, 1e-6}) {
      SwitchingOptions sw;
      sw.zeno_time = zeno;
      SimulationOptions o;
      o.rtol = o.atol = 1e-10;
      const ImpactOutcome r = resolve_impact(*model, active, 0.0, q, qd, o, sw);
      ++trials;
      sweeps += r.cone_sweeps;
      fallbacks += r.cone_fallbacks;
      unsolved += r.cone_unsolved;
      newton_steps += r.cone_newton_steps;
      if (!r.ok) {
        BOOST_TEST(r.message.find("the impact at t = 0 (contacts 'c1'") != std::string::npos, r.message);
        ++refused;
        ++refused_by[nc];
        if (refused <= 3) BOOST_TEST_MESSAGE("refused: " << r.message);
        continue;
      }
      ++impacts;
      if (nc > 1) ++several;
      limited += r.energy_limited;
      double T0 = 0, T1 = 0;
      for (int i = 0; i < 4; ++i) {
        T0 += 0.5 * mass[i] * qd.segment<3>(3 * i).squaredNorm();
        T1 += 0.5 * mass[i] * r.qd_after.segment<3>(3 * i).squaredNorm();
      }
      worst_gain = std::max(worst_gain, (T1 - T0) / T0);
      BOOST_TEST(T1 <= T0 * (1 + 1e-10), "trial " << trial << " (" << nc << " contacts, zeno " << zeno << "): T " << T0 << " -> " << T1);
      BOOST_TEST(std::abs(r.energy_change - (T1 - T0)) <= 1e-9 * T0);
      for (int k = 0; k < nc; ++k) {
        const double vn_after = normals[k].dot(r.qd_after.segment<3>(3 * k));
        BOOST_TEST(vn_after >= -1e-8 * (1 + qd.norm()), "trial " << trial << ": contact " << k << " still approaches: " << vn_after);
      }
      for (const ContactEvent& e : r.events) {
        const std::string K = e.constraint.substr(1);
        BOOST_TEST(e.normal >= -1e-12);
        BOOST_TEST(e.tangential >= 0.0);  // a cone's magnitude
        BOOST_TEST(e.tangential <= p["mu" + K] * e.normal * (1 + 1e-9) + 1e-12,
                   "trial " << trial << ": |Lambda_t| " << e.tangential << " outside the cone of " << e.normal);
        // The laws where Newton's impulse was taken (neither limited by the energy rule nor
        // replaced by an accumulation's closure, which a rebound above 1e-5 m/s is not): an
        // approaching contact with an impulse leaves at −e v_n⁻, and one that slides after it
        // has its friction impulse on the cone's boundary.
        const double vtol = 1e-8 * (1 + qd.norm());
        if (zeno == 0.0 && !r.energy_limited && e.normal > 1e-9 && -p["e" + K] * e.vn_before > 1e-5) {
          ++newton_checked;
          BOOST_TEST(std::abs(e.vn_after + p["e" + K] * e.vn_before) <= vtol,
                     "trial " << trial << ": " << e.constraint << " leaves at " << e.vn_after << ", not " << -p["e" + K] * e.vn_before);
        }
        if (zeno == 0.0 && !r.energy_limited && e.vt_after > vtol && p["mu" + K] > 0.0) {
          ++slide_checked;
          BOOST_TEST(e.tangential >= p["mu" + K] * e.normal * (1 - 1e-9) - 1e-12,
                     "trial " << trial << ": " << e.constraint << " slides on at " << e.vt_after << " inside its cone");
        }
      }
      // The rods hold through the impulse: the velocities stay rigid.
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const Eigen::Vector3d d = q.segment<3>(3 * j) - q.segment<3>(3 * i);
          const Eigen::Vector3d dv = r.qd_after.segment<3>(3 * j) - r.qd_after.segment<3>(3 * i);
          BOOST_TEST(std::abs(d.dot(dv)) <= 1e-9 * (1 + qd.norm()));
        }
    }
  }
  BOOST_TEST_MESSAGE(trials << " resolutions (" << cones << " cones), " << refused << " refused, " << impacts << " impacts ("
                            << several << " with several contacts), " << limited
                            << " limited by the energy rule; largest relative change of T " << worst_gain);
  BOOST_TEST_MESSAGE("refused with 1, 2, 3 contacts: " << refused_by[1] << ", " << refused_by[2] << ", " << refused_by[3]);
  BOOST_TEST_MESSAGE(sweeps << " Gauss-Seidel sweeps; " << fallbacks << " problems handed to the fallback, " << unsolved
                            << " of them without a solution found (the impact then plastic), in " << newton_steps
                            << " steps; Newton's law checked at " << newton_checked
                            << " contacts, the slide on the cone's boundary at " << slide_checked << "; "
                            << std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count()
                            << " s");
  BOOST_TEST(refused == 0);
  BOOST_TEST(unsolved <= 4);  // the two wedged impacts above, with and without zeno_time
  BOOST_TEST(several > 300);
}

// A tripod at rest: the tetrahedron standing on three vertices on a level floor, each with a
// 2-D cone. Its six friction rows pose three conditions (the floor holds the body's planar
// motion three times over): the mode decision's contact-by-contact solve converges on the
// singular system, the dependent friction rows are implied (Huang's rank test), and the body
// stays at rest, carrying its weight on the three normals as statics says: the apex's weight
// split by the barycentric coordinates of its projection in the base triangle (1e-9 relative).
namespace {
constexpr double kTripodZ = 40.0;
const Eigen::Vector3d kBase[3] = {{500.0, -200.0, kTripodZ}, {500.6, -200.1, kTripodZ}, {500.2, -199.5, kTripodZ}};
const Eigen::Vector3d kApex(500.25, -199.8, kTripodZ + 0.5);
// The tetrahedron standing on its first three vertices on the level floor z = kTripodZ, each
// with a 2-D cone of coefficient mu along x and y; masses 0.5 kg at the base, 2 kg at the apex.
std::shared_ptr<const Model> tripod(double mu, Eigen::VectorXd& q) {
  static const auto desc = modelfile::load_model_text(tetrahedron_text(), "tetrahedron_on_planes.toml");
  q.resize(12);
  for (int i = 0; i < 3; ++i) q.segment<3>(3 * i) = kBase[i];
  q.segment<3>(9) = kApex;
  std::map<std::string, double> p{{"m1", 0.5}, {"m2", 0.5}, {"m3", 0.5}, {"m4", 2.0}};
  for (int k = 1; k <= 3; ++k) {
    const std::string K = std::to_string(k);
    p["nz" + K] = 1.0;
    p["ax" + K] = 1.0;
    p["by" + K] = 1.0;
    p["d" + K] = kTripodZ;
    p["mu" + K] = mu;
  }
  return desc->instantiate(p, q, 0.0);
}
}  // namespace

BOOST_AUTO_TEST_CASE(a_tripod_with_three_cones_stands_still_carrying_its_weight_as_statics_splits_it) {
  const double g = 9.81;
  Eigen::VectorXd q, qd = Eigen::VectorXd::Zero(12);
  auto model = tripod(0.5, q);
  const Eigen::Vector3d* base = kBase;
  const Eigen::Vector3d& apex = kApex;
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  o.active_constraints = all_constraints(*model);
  Trace tr;
  const auto r = run(*model, q, qd, 1.0, o, {}, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  BOOST_TEST(r.events.empty());
  for (int c = 0; c < 3; ++c) BOOST_TEST((tr.modes.back()[c] == ContactMode::stick));
  BOOST_TEST((r.q_end - q).cwiseAbs().maxCoeff() < 1e-12);
  // Statics: the base particles' own weights on their vertices, the apex's split by the
  // barycentric coordinates of (apex_x, apex_y) in the base triangle.
  Eigen::Matrix3d A;
  for (int i = 0; i < 3; ++i) A.col(i) << base[i].x(), base[i].y(), 1.0;
  const Eigen::Vector3d w = A.fullPivLu().solve(Eigen::Vector3d(apex.x(), apex.y(), 1.0));
  const auto& names = model->derived_names();
  for (int i = 0; i < 3; ++i) {
    const auto at = std::find(names.begin(), names.end(), "N" + std::to_string(i + 1)) - names.begin();
    const double N = tr.derived.back()[at];
    const double want = 0.5 * g + w[i] * 2.0 * g;
    BOOST_TEST_MESSAGE("vertex " << i + 1 << ": normal force " << N << " N, statics " << want << " N");
    BOOST_TEST(std::abs(N - want) < 1e-9 * want);
  }
}

// The tripod launched sideways slides in translation: the three cones' friction totals mu M g
// against the motion (the normal forces shift towards the front, but their moment about the
// vertical through the centre of mass stays zero, so it does not turn), and all three stop at
// v0/(mu g) after v0²/(2 mu g), where the mode decision of three cones at rest, with six friction
// rows on three conditions, makes them all stick (1e-10 relative: the translation is polynomial).
BOOST_AUTO_TEST_CASE(a_tripod_launched_sideways_stops_with_its_three_cones_at_the_closed_form_instant) {
  const double g = 9.81, mu = 0.3, v0 = 0.9;
  Eigen::VectorXd q, qd = Eigen::VectorXd::Zero(12);
  auto model = tripod(mu, q);
  const Eigen::Vector3d dir = Eigen::Vector3d(0.6, -0.8, 0.0);
  for (int i = 0; i < 4; ++i) qd.segment<3>(3 * i) = v0 * dir;
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  o.active_constraints = all_constraints(*model);
  const auto r = run(*model, q, qd, 0.5, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double ts = v0 / (mu * g), d = v0 * v0 / (2 * mu * g);
  const auto sticks = events_of(r, ContactEventKind::stick);
  BOOST_TEST(sticks.size() == 3u);
  BOOST_TEST(r.events.size() == 3u);
  for (const auto& e : sticks) BOOST_TEST(std::abs(e.t - ts) < 1e-10 * ts, e.constraint << " sticks at " << e.t);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d moved = r.q_end.segment<3>(3 * i) - q.segment<3>(3 * i);
    BOOST_TEST((moved - d * dir).norm() < 1e-10 * d, "vertex " << i + 1 << " moved " << moved.transpose());
  }
  BOOST_TEST(r.qd_end.norm() < 1e-12);
}
