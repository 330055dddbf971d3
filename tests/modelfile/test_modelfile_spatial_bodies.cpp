// Spatial rigid bodies in Euler parameters (models/tumbling_body.toml, models/top_heavy.toml,
// models/rolling_coin.toml, written by scripts/make_spatial_models.py; docs/bodies-spatial.md),
// each against an oracle that is not pcsim's model file:
// - the regularization 1/2 k (e . e_d)^2 that makes M positive definite changes neither q_dd nor
//   R on the constraint manifold (the proof in the docs; here: k scaled by 1e-2 and 1e2 at random
//   states gives the same q_dd and R to rounding, and k = 0 leaves M singular);
// - a free asymmetric body near its intermediate axis flips (Dzhanibekov) as Euler's equations
//   integrated by this test's own RK4 say, with energy and |angular momentum| conserved;
// - the heavy symmetric top started in steady precession keeps the closed-form rate
//   Omega (I3 w3 - I1 Omega cos(theta)) = m g l and its nutation angle;
// - a coin started in steady circular rolling keeps its tilt and the closed-form circle
//   Omega^2 = g tan(beta) / (3 Rc / 2 + r sin(beta) / 4);
// - spatial bushings (issue 22): the small-rotation period 2 pi sqrt(J/k) about each axis, the
//   measure 2 sin(phi/2) n against Eigen's axis-angle extraction, the damping about marker1's
//   axes, the static sag m g / k and turn tan(phi) = m g l / k, energy, and the half turn.
#define BOOST_TEST_MODULE modelfile_spatial_bodies
#include <boost/test/unit_test.hpp>
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile/model_source.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::Vector4d;

namespace {

// G(e) (body-frame rates w' = 2 G e_d) and E(e) (ground-frame rates w = 2 E e_d).
Eigen::Matrix<double, 3, 4> G_of(const Vector4d& e) {
  Eigen::Matrix<double, 3, 4> G;
  G << -e[1], e[0], e[3], -e[2], -e[2], -e[3], e[0], e[1], -e[3], e[2], -e[1], e[0];
  return G;
}
Eigen::Matrix<double, 3, 4> E_of(const Vector4d& e) {
  Eigen::Matrix<double, 3, 4> E;
  E << -e[1], e[0], -e[3], e[2], -e[2], e[3], e[0], -e[1], -e[3], -e[2], e[1], e[0];
  return E;
}
// A(e) = E G^T for |e| = 1 (the rotation body -> ground).
Matrix3d A_of(const Vector4d& e) { return E_of(e) * G_of(e).transpose(); }

// A state of a body model: (x, y, z, e0..e3) and velocities (e_d = 1/2 E^T w for a ground-frame
// angular velocity w: E E^T = I and E e = 0 on |e| = 1, so e . e_d = 0).
struct State {
  Eigen::VectorXd q = Eigen::VectorXd(7), qd = Eigen::VectorXd(7);
};
State body_state(const Vector3d& r, const Vector4d& e, const Vector3d& v, const Vector3d& w) {
  State s;
  s.q << r, e;
  s.qd << v, 0.5 * E_of(e).transpose() * w;
  return s;
}

std::vector<std::string> all_constraints(const mech::Model& m) {
  std::vector<std::string> names;
  for (const auto& c : m.constraints()) names.push_back(c.name);
  return names;
}

}  // namespace

// At 20 random states on the manifold (|e| = 1, e . e_d = 0, random positions and velocities
// otherwise) of each model, q_dd and R with k scaled by 1e-2 and by 1e2 equal those with the
// chosen k to 1e-9 relative (M's condition changes by 1e2, so rounding grows to ~1e-12), and
// with k = 0, M (7 x 7) has a zero eigenvalue (the reason for the term).
BOOST_AUTO_TEST_CASE(euler_parameter_regularization_changes_neither_accelerations_nor_reactions) {
  std::mt19937 rng(22);
  for (const char* file : {"tumbling_body.toml", "top_heavy.toml", "rolling_coin.toml"}) {
    const auto desc = load_model_file(model_path(file));
    const std::string b = desc->coordinates()[0].substr(0, desc->coordinates()[0].size() - 2);
    const auto base = desc->instantiate({});
    const auto zero = desc->instantiate({{b + "_kscale", 0.0}});
    std::vector<int> rows;
    for (int i = 0; i < static_cast<int>(base->constraints().size()); ++i) rows.push_back(i);
    double worst = 0, min_eig_zero = 1e300, min_eig_base = 1e300;
    for (double scale : {1e-2, 1e2}) {
      const auto other = desc->instantiate({{b + "_kscale", scale}});
      mech::Dynamics d1(*base, Kernel::cpp), d2(*other, Kernel::cpp);
      const auto set1 = mech::ActiveSet::of(*base, rows), set2 = mech::ActiveSet::of(*other, rows);
      for (int k = 0; k < 20; ++k) {
        Vector4d e(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
        e.normalize();
        const Vector3d r(100 * uniform(rng), 100 * uniform(rng), 0.3 + 0.01 * uniform(rng));
        const Vector3d v(uniform(rng), uniform(rng), uniform(rng));
        const Vector3d w(5 * uniform(rng), 5 * uniform(rng), 5 * uniform(rng));
        const State s = body_state(r, e, v, w);
        BOOST_REQUIRE(d1.evaluate(set1, 0.0, s.q, s.qd) == mech::ModelIssue::none);
        BOOST_REQUIRE(d1.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
        BOOST_REQUIRE(d2.evaluate(set2, 0.0, s.q, s.qd) == mech::ModelIssue::none);
        BOOST_REQUIRE(d2.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
        worst = std::max(worst, rel_diff(d2.qdd, d1.qdd, 1.0));
        worst = std::max(worst, rel_diff(d2.R, d1.R, 1.0));
        Eigen::MatrixXd M(7, 7);
        Eigen::VectorXd h(7);
        zero->kinetic_terms(0.0, s.q, s.qd, M, h);
        min_eig_zero = std::min(min_eig_zero, Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().minCoeff());
        base->kinetic_terms(0.0, s.q, s.qd, M, h);
        const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues();
        min_eig_base = std::min(min_eig_base, ev.minCoeff() / ev.maxCoeff());
      }
    }
    BOOST_TEST_MESSAGE(file << ": max relative change of q_dd, R with k x 1e-2, x 1e2: " << worst
                            << "; min eigenvalue of M with k = 0: " << min_eig_zero
                            << "; min eig/max eig with k: " << min_eig_base);
    BOOST_TEST(worst < 1e-9);
    BOOST_TEST(std::abs(min_eig_zero) < 1e-12);
    BOOST_TEST(min_eig_base > 1e-3);  // positive definite, conditioned like the body's inertia
  }
}

// Euler's equations J w_d + w x J w = 0 and e_d = 1/2 G^T w, integrated by RK4 with h = 1e-3
// (its error is below 1e-11 over the run: halving h changes w by < 1e-11), started at
// w = (0.15, 3, 0.15) rad/s near the intermediate axis of J = (0.1, 0.2, 0.3): w2 changes sign
// every ~4 s (the flip). pcsim (rtol = atol = 1e-10) must follow w and e through three flips to
// 1e-5 (the passages near the unstable axis amplify integration errors), and keep the energy and
// |H| to 1e-7 relative. Measured: w error 1.9e-5, 3.0e-6, 4.4e-7, 7.2e-8 and energy error 1.8e-7,
// 3.8e-8, 8.9e-9, 1.7e-9 at rtol = 1e-9 ... 1e-12: the integrator's error, shrinking with rtol
// (not a model error). The body's centre of mass sits 1000 m from the origin and drifts uniformly.
BOOST_AUTO_TEST_CASE(tumbling_asymmetric_body_flips_as_eulers_equations_say) {
  const auto desc = load_model_file(model_path("tumbling_body.toml"));
  const auto model = desc->instantiate({});
  const Vector3d J(0.1, 0.2, 0.3);
  Vector4d e0(0.9, 0.1, 0.3, 0.2);
  e0.normalize();
  const Vector3d wb0(0.15, 3.0, 0.15);
  const State s0 = body_state(Vector3d(1000, -800, 500), e0, Vector3d(0.3, -0.2, 0.1),
                              A_of(e0) * wb0);
  // The oracle on a grid of 0.01 s.
  using Y = Eigen::Matrix<double, 7, 1>;
  auto f = [&](const Y& y) {
    const Vector3d w = y.head<3>();
    const Vector4d e = y.tail<4>();
    Y d;
    d.head<3>() = -(w.cross(J.cwiseProduct(w))).cwiseQuotient(J);
    d.tail<4>() = 0.5 * G_of(e).transpose() * w;
    return d;
  };
  const double t_end = 13.0, grid = 0.01;
  const int n_grid = static_cast<int>(std::lround(t_end / grid));
  std::vector<Y> oracle(n_grid + 1);
  Y y;
  y << wb0, e0;
  oracle[0] = y;
  const int sub = 10;
  const double h = grid / sub;
  int flips = 0;
  for (int k = 1; k <= n_grid; ++k) {
    for (int j = 0; j < sub; ++j) {
      const Y k1 = f(y), k2 = f(y + 0.5 * h * k1), k3 = f(y + 0.5 * h * k2), k4 = f(y + h * k3);
      y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    if (y[1] * oracle[k - 1][1] < 0) ++flips;
    oracle[k] = y;
  }
  BOOST_TEST_REQUIRE(flips >= 3);
  const double E0 = 0.5 * wb0.dot(J.cwiseProduct(wb0)) + 0.5 * 2.0 * s0.qd.head<3>().squaredNorm();
  const double H0 = J.cwiseProduct(wb0).norm();
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_constraints(*model);
  double err_w = 0, err_e = 0, err_E = 0, err_H = 0, err_r = 0;
  int next = 0, pcsim_flips = 0;
  double prev_w2 = wb0[1];
  const mech::SimulationResult r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
    while (next <= n_grid && next * grid <= v.t + 1e-12) {
      const mech::Sample s = v.at(std::max(v.t_prev, next * grid));
      const Y& yo = oracle[next];
      // outputs: w1 w2 w3 H1 H2 H3 H energy
      err_w = std::max(err_w, (s.derived.head<3>() - yo.head<3>()).cwiseAbs().maxCoeff());
      err_e = std::max(err_e, (s.q.tail<4>() - yo.tail<4>()).cwiseAbs().maxCoeff());
      err_E = std::max(err_E, std::abs(s.derived[7] - E0) / E0);
      err_H = std::max(err_H, std::abs(s.derived[6] - H0) / H0);
      const Vector3d rc = s0.q.head<3>() + s.t * s0.qd.head<3>();
      err_r = std::max(err_r, (s.q.head<3>() - rc).cwiseAbs().maxCoeff());
      if (s.derived[1] * prev_w2 < 0) ++pcsim_flips;
      prev_w2 = s.derived[1];
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("tumbling body: " << flips << " flips (oracle), " << pcsim_flips
                     << " (pcsim); max error w " << err_w << " rad/s, e " << err_e
                     << ", energy rel " << err_E << ", |H| rel " << err_H << ", r " << err_r << " m");
  BOOST_TEST(next == n_grid + 1);
  BOOST_TEST(pcsim_flips == flips);
  BOOST_TEST(err_w < 1e-5);
  BOOST_TEST(err_e < 1e-5);
  BOOST_TEST(err_E < 1e-7);
  BOOST_TEST(err_H < 1e-7);
  BOOST_TEST(err_r < 1e-7);
}

// The heavy symmetric top (J1 = J2 = 0.005, J3 = 0.008 kg m^2 about the centre of mass, m = 1 kg,
// l = 0.1 m, pivot at (500, -300, 100) m) started in steady precession: nutation angle theta =
// 0.5 rad, axial spin w3 = 40 rad/s, precession Omega the slow root of
// I1 cos(theta) Omega^2 - I3 w3 Omega + m g l = 0 (I1 = J1 + m l^2 about the pivot, I3 = J3),
// ~3.6 rad/s. Over 4 precession turns (~7 s) the axis must stay at theta and turn at Omega:
// k(t) = (sin(theta) sin(Omega t), -sin(theta) cos(Omega t), cos(theta)) to 1e-6, the
// precession output at Omega to 1e-6 relative, and the spin at w3 to 1e-6 relative.
BOOST_AUTO_TEST_CASE(heavy_symmetric_top_precesses_at_the_closed_form_rate) {
  const auto desc = load_model_file(model_path("top_heavy.toml"));
  const Vector3d P(500, -300, 100);
  const auto model = desc->instantiate({{"X0", P[0]}, {"Y0", P[1]}, {"Z0", P[2]}});
  const double m = 1.0, l = 0.1, g = 9.81, J1 = 0.005, J3 = 0.008;
  const double theta = 0.5, w3 = 40.0, I1 = J1 + m * l * l, I3 = J3;
  const double a = I1 * std::cos(theta), bq = -I3 * w3, c = m * g * l;
  const double Omega = (-bq - std::sqrt(bq * bq - 4 * a * c)) / (2 * a);
  const Vector4d e0(std::cos(theta / 2), std::sin(theta / 2), 0, 0);  // about x by theta
  const Vector3d k0(0, -std::sin(theta), std::cos(theta));
  BOOST_REQUIRE((A_of(e0).col(2) - k0).norm() < 1e-15);
  const Vector3d w = Omega * Vector3d::UnitZ() + (w3 - Omega * std::cos(theta)) * k0;
  const State s0 = body_state(P + l * k0, e0, w.cross(l * k0), w);
  mech::SimulationOptions o;
  o.t_end = 4 * 2 * M_PI / Omega;
  o.rtol = o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_constraints(*model);
  double err_k = 0, err_prec = 0, err_spin = 0, err_E = 0;
  const double E0 = 0.5 * m * s0.qd.head<3>().squaredNorm() +
                    0.5 * (J1 * (w.squaredNorm() - std::pow(w.dot(k0), 2)) + J3 * std::pow(w.dot(k0), 2)) +
                    m * g * s0.q[2];
  const mech::SimulationResult r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const double t = s.t;
    const Vector3d k(std::sin(theta) * std::sin(Omega * t), -std::sin(theta) * std::cos(Omega * t),
                     std::cos(theta));
    // outputs: kx ky kz spin precession energy
    err_k = std::max(err_k, (s.derived.head<3>() - k).cwiseAbs().maxCoeff());
    err_spin = std::max(err_spin, std::abs(s.derived[3] - w3) / w3);
    err_prec = std::max(err_prec, std::abs(s.derived[4] - Omega) / Omega);
    err_E = std::max(err_E, std::abs(s.derived[5] - E0) / std::abs(E0));
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("heavy top: Omega " << Omega << " rad/s, t_end " << o.t_end << " s; max error axis "
                     << err_k << ", precession rel " << err_prec << ", spin rel " << err_spin
                     << ", energy rel " << err_E);
  BOOST_TEST(err_k < 1e-6);
  BOOST_TEST(err_prec < 1e-6);
  BOOST_TEST(err_spin < 1e-6);
  BOOST_TEST(err_E < 1e-8);
}

// The same top as a body on a spherical tree joint (models/top_heavy_bodies.toml: four
// coordinates, the Euler parameters of the top relative to the pivot's frame, and their norm
// row, against the seven coordinates and four rows above), started in the same steady
// precession: the same closed forms to the same bounds, and the outputs of the two models equal
// at every step's end to 1e-9 (the axis, the spin relative to w3, the precession relative to
// Omega, the energy relative to E0; the two are integrated with their own steps, at rtol 1e-12
// so that their integration errors stay below that).
BOOST_AUTO_TEST_CASE(heavy_symmetric_top_on_a_spherical_tree_joint_precesses_at_the_closed_form_rate) {
  const auto desc = load_model_file(model_path("top_heavy_bodies.toml"));
  const Vector3d P(500, -300, 100);
  const auto model = desc->instantiate({{"X0", P[0]}, {"Y0", P[1]}, {"Z0", P[2]}});
  BOOST_REQUIRE(desc->coordinates().size() == 4u);
  const double m = 1.0, l = 0.1, g = 9.81, J1 = 0.005, J3 = 0.008;
  const double theta = 0.5, w3 = 40.0, I1 = J1 + m * l * l, I3 = J3;
  const double a = I1 * std::cos(theta), bq = -I3 * w3, c = m * g * l;
  const double Omega = (-bq - std::sqrt(bq * bq - 4 * a * c)) / (2 * a);
  const Vector4d e0(std::cos(theta / 2), std::sin(theta / 2), 0, 0);
  const Vector3d k0(0, -std::sin(theta), std::cos(theta));
  const Vector3d w = Omega * Vector3d::UnitZ() + (w3 - Omega * std::cos(theta)) * k0;
  const State s0 = body_state(P + l * k0, e0, w.cross(l * k0), w);  // the energy form's state
  const Eigen::VectorXd q = s0.q.segment<4>(3), qd = s0.qd.segment<4>(3);  // the joint's p, ṗ
  mech::SimulationOptions o;
  o.t_end = 4 * 2 * M_PI / Omega;
  o.rtol = o.atol = 1e-12;  // tighter than above: the two models' difference is then theirs
  o.kernel = Kernel::cpp;
  o.active_constraints = all_constraints(*model);
  const double E0 = 0.5 * m * s0.qd.head<3>().squaredNorm() +
                    0.5 * (J1 * (w.squaredNorm() - std::pow(w.dot(k0), 2)) + J3 * std::pow(w.dot(k0), 2)) +
                    m * g * s0.q[2];
  double err_k = 0, err_prec = 0, err_spin = 0, err_E = 0;
  std::vector<std::pair<double, Eigen::VectorXd>> tree;
  const mech::SimulationResult r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const Vector3d k(std::sin(theta) * std::sin(Omega * s.t), -std::sin(theta) * std::cos(Omega * s.t),
                     std::cos(theta));
    err_k = std::max(err_k, (s.derived.head<3>() - k).cwiseAbs().maxCoeff());
    err_spin = std::max(err_spin, std::abs(s.derived[3] - w3) / w3);
    err_prec = std::max(err_prec, std::abs(s.derived[4] - Omega) / Omega);
    err_E = std::max(err_E, std::abs(s.derived[5] - E0) / std::abs(E0));
    tree.push_back({s.t, s.derived.head<6>()});
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  // The energy form, sampled at the tree model's step ends.
  const auto edesc = load_model_file(model_path("top_heavy.toml"));
  const auto emodel = edesc->instantiate({{"X0", P[0]}, {"Y0", P[1]}, {"Z0", P[2]}});
  o.active_constraints = all_constraints(*emodel);
  std::size_t next = 0;
  double diff = 0;
  const mech::SimulationResult re = mech::simulate(*emodel, s0.q, s0.qd, o, [&](const mech::StepView& v) {
    for (; next < tree.size() && tree[next].first <= v.t; ++next) {
      const mech::Sample s = v.sample(std::max(v.t_prev, tree[next].first));
      const Eigen::VectorXd& d = tree[next].second;
      diff = std::max({diff, (s.derived.head<3>() - d.head<3>()).cwiseAbs().maxCoeff(),
                       std::abs(s.derived[3] - d[3]) / w3, std::abs(s.derived[4] - d[4]) / Omega,
                       std::abs(s.derived[5] - d[5]) / std::abs(E0)});
    }
    return true;
  });
  BOOST_REQUIRE(re.status == mech::SimulationStatus::success);
  BOOST_TEST(next == tree.size());
  BOOST_TEST_MESSAGE("heavy top on a spherical tree joint: max error axis " << err_k << ", precession rel "
                     << err_prec << ", spin rel " << err_spin << ", energy rel " << err_E
                     << "; against the energy form " << diff);
  BOOST_TEST(err_k < 1e-6);
  BOOST_TEST(err_prec < 1e-6);
  BOOST_TEST(err_spin < 1e-6);
  BOOST_TEST(err_E < 1e-8);
  BOOST_TEST(diff < 1e-9);
}

// A coin (r = 0.05 m, thin disk) leaning into the turn by beta = 0.3 rad, its centre on a circle
// of radius Rc = 0.5 m: Newton-Euler in the frame turning with the heading (docs/bodies-spatial.md)
// gives Omega^2 = g tan(beta) / (3 Rc/2 + r sin(beta)/4) and the spin about its axis
// s = Omega (Rc/r + sin(beta)). Started there, 2 km from the origin, over 3 full turns of the
// heading (~9 s; the spin angle turns ~30 times) the centre must stay on the circle, at the
// closed-form angle, to 1e-6 m, the tilt at beta to 1e-6, and the energy to 1e-8 relative.
BOOST_AUTO_TEST_CASE(rolling_coin_rolls_steadily_on_the_closed_form_circle) {
  const auto desc = load_model_file(model_path("rolling_coin.toml"));
  const auto model = desc->instantiate({});
  const double m = 0.1, rr = 0.05, g = 9.81, beta = 0.3, Rc = 0.5;
  const double Omega = std::sqrt(g * std::tan(beta) / (1.5 * Rc + rr * std::sin(beta) / 4));
  const double spin = Omega * (Rc / rr + std::sin(beta));
  // Body axes in ground: x along the heading (ground x), z the disk's axis (0, cos b, -sin b),
  // y = z x x: a rotation about ground x by gamma = -pi/2 - beta.
  const double gamma = -M_PI / 2 - beta;
  const Vector4d e0(std::cos(gamma / 2), std::sin(gamma / 2), 0, 0);
  const Vector3d kax(0, std::cos(beta), -std::sin(beta));
  BOOST_REQUIRE((A_of(e0).col(2) - kax).norm() < 1e-15);
  const Vector3d Pc(2000, 1000, 0);
  const Vector3d d(0, std::sin(beta), std::cos(beta));  // contact -> centre, unit
  const Vector3d C0 = Pc + rr * d;
  const Vector3d w = Omega * Vector3d::UnitZ() + spin * kax;
  const Vector3d vC = w.cross(rr * d);
  BOOST_REQUIRE(std::abs(vC[0] - Omega * Rc) < 1e-12 && vC.tail<2>().norm() < 1e-12);
  const Vector3d O = C0 + Vector3d(0, Rc, 0);  // the centre of the centre's circle
  const State s0 = body_state(C0, e0, vC, w);
  const double E0 = 0.5 * m * vC.squaredNorm() +
                    0.5 * (m * rr * rr / 4 * (w.squaredNorm() - std::pow(w.dot(kax), 2)) +
                           m * rr * rr / 2 * std::pow(w.dot(kax), 2)) + m * g * C0[2];
  mech::SimulationOptions o;
  o.t_end = 3 * 2 * M_PI / Omega;
  o.rtol = o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_constraints(*model);
  double err_c = 0, err_tilt = 0, err_E = 0, res = 0;
  const mech::SimulationResult r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const double t = s.t;
    const Vector3d C = O + Rc * Vector3d(std::sin(Omega * t), -std::cos(Omega * t), 0) +
                       Vector3d(0, 0, C0[2] - O[2]);
    err_c = std::max(err_c, (s.q.head<3>() - C).cwiseAbs().maxCoeff());
    // outputs: tilt px py energy; tilt = asin(n_z) = -beta
    err_tilt = std::max(err_tilt, std::abs(s.derived[0] + beta));
    err_E = std::max(err_E, std::abs(s.derived[3] - E0) / E0);
    res = std::max(res, s.residual_vel);
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("rolling coin: Omega " << Omega << " rad/s, spin " << spin << " rad/s, t_end "
                     << o.t_end << " s; max error centre " << err_c << " m, tilt " << err_tilt
                     << " rad, energy rel " << err_E << ", residual_vel " << res);
  BOOST_TEST(err_c < 1e-6);
  BOOST_TEST(err_tilt < 1e-6);
  BOOST_TEST(err_E < 1e-8);
}

// ---- generated kinematics of spatial bodies (issue 22) ----------------------------------------

namespace {

// A free asymmetric body (J = 0.1, 0.2, 0.3 about its centre of mass, the frame origin), no
// gravity, with a marker p off every axis; outputs: the marker's acceleration, the angular
// velocity (ground and body axes) and acceleration (ground and body axes).
const char* kFreeBody = R"([model]
name = "free_body"
[model.body.b]
kind = "spatial"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
markers = { p = [0.3, -0.2, 0.5] }
[model.outputs]
ax = "b_p_ax"
ay = "b_p_ay"
az = "b_p_az"
wx = "b_wx"
wy = "b_wy"
wz = "b_wz"
w1 = "b_w1"
w2 = "b_w2"
w3 = "b_w3"
alx = "b_alphax"
aly = "b_alphay"
alz = "b_alphaz"
al1 = "b_alpha1"
al2 = "b_alpha2"
al3 = "b_alpha3"
)";

// The outputs of a model at a state, with q̈ from the engine's solve (every row imposed).
Eigen::VectorXd outputs_at(const mech::Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(model.constraints().size()); ++i) rows.push_back(i);
  mech::Dynamics dyn(model, Kernel::cpp);
  const auto set = mech::ActiveSet::of(model, rows);
  BOOST_REQUIRE(dyn.evaluate(set, 0.0, q, qd) == mech::ModelIssue::none);
  BOOST_REQUIRE(dyn.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
  Eigen::VectorXd out(static_cast<Eigen::Index>(model.derived_names().size()));
  model.derived(0.0, q, qd, dyn.qdd, dyn.R, out);
  return out;
}

}  // namespace

// A free body spinning at constant ω about a principal axis (each of the three, at 5 random
// orientations, 1000 m from the origin, drifting at a uniform velocity) is in steady rotation:
// Euler's equations give ω̇ = 0, so the marker's acceleration is exactly −ω² r_⊥ (r_⊥ the
// marker's offset from the axis through the centre of mass), and every angular-acceleration
// output is 0; the angular velocity outputs are ω in ground and in body axes. To 1e-12 of ω² |r|
// (rounding).
BOOST_AUTO_TEST_CASE(marker_on_a_body_spinning_about_a_principal_axis_accelerates_by_minus_omega_squared_r_perp) {
  const auto desc = load_model_text(kFreeBody, "free_body.toml");
  const auto model = desc->instantiate({});
  std::mt19937 rng(12);
  const Vector3d p(0.3, -0.2, 0.5);
  double worst = 0.0;
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 0; k < 5; ++k) {
      Vector4d e(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
      e.normalize();
      const Matrix3d A = A_of(e);
      const double w = 7.0 * uniform(rng);
      const Vector3d wb = w * Vector3d::Unit(axis), wg = A * wb;
      const State s = body_state(Vector3d(1000, -1000, 500), e, Vector3d(0.4, 0.1, -0.3), wg);
      const Eigen::VectorXd out = outputs_at(*model, s.q, s.qd);
      const Vector3d r = A * p, n = wg.normalized();
      const Vector3d a = -w * w * (r - r.dot(n) * n);
      const double scale = w * w * r.norm();
      for (int i = 0; i < 3; ++i) {
        worst = std::max({worst, std::abs(out[i] - a[i]) / scale, std::abs(out[3 + i] - wg[i]) / std::abs(w),
                          std::abs(out[6 + i] - wb[i]) / std::abs(w), std::abs(out[9 + i]) / scale,
                          std::abs(out[12 + i]) / scale});
      }
    }
  BOOST_TEST_MESSAGE("worst relative difference from -w^2 r_perp, 0 and w: " << worst);
  BOOST_TEST(worst < 1e-12);
}

// The angular acceleration outputs of a free asymmetric body follow Euler's equations
// α' = J⁻¹ (−ω' × J ω') in body axes (b_alpha1..3) and α = A α' in ground axes (b_alphax..z),
// and the marker's acceleration is a_c + α × r + ω × (ω × r) (rigid-body kinematics, the centre of
// mass unaccelerated), at 20 random states: to 1e-11 of the scale (rounding of the solve).
BOOST_AUTO_TEST_CASE(angular_acceleration_of_an_asymmetric_body_follows_eulers_equations) {
  const auto desc = load_model_text(kFreeBody, "free_body.toml");
  const auto model = desc->instantiate({});
  std::mt19937 rng(21);
  const Vector3d J(0.1, 0.2, 0.3), p(0.3, -0.2, 0.5);
  double worst = 0.0;
  for (int k = 0; k < 20; ++k) {
    Vector4d e(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
    e.normalize();
    const Matrix3d A = A_of(e);
    const Vector3d wb = 5.0 * Vector3d(uniform(rng), uniform(rng), uniform(rng));
    const State s = body_state(Vector3d(-1000, 2000, 300), e, Vector3d(1, 2, 3), A * wb);
    const Eigen::VectorXd out = outputs_at(*model, s.q, s.qd);
    const Vector3d alb = -(wb.cross(J.cwiseProduct(wb))).cwiseQuotient(J);
    const Vector3d alg = A * alb, wg = A * wb, r = A * p;
    const Vector3d a = alg.cross(r) + wg.cross(wg.cross(r));
    const double scale = alb.norm() + wb.squaredNorm();
    for (int i = 0; i < 3; ++i)
      worst = std::max({worst, std::abs(out[12 + i] - alb[i]) / scale, std::abs(out[9 + i] - alg[i]) / scale,
                        std::abs(out[i] - a[i]) / (scale * r.norm())});
  }
  BOOST_TEST_MESSAGE("worst relative difference from Euler's equations: " << worst);
  BOOST_TEST(worst < 1e-11);
}

// A gyrostat: a spatial body in Euler parameters carrying a rotor on a revolute tree joint (the
// rotor's pose and rates go through the carrier's definitions), tumbling freely for 1 s
// (rtol 1e-12): at every point of a 1 ms grid the rotor marker's acceleration and the rotor's
// angular acceleration (ground axes) equal the central differences of the velocity columns to
// the difference's truncation error h²/6 |ä| (ä, its largest over [t − h, t + h], from the second
// difference of the acceleration column; 1.5 times that plus 1e-8/h: Radau's dense output between steps, the collocation polynomial, is good to ~1e-9 here, not to rtol).
BOOST_AUTO_TEST_CASE(spatial_tree_body_accelerations_are_the_central_differences_of_their_velocities) {
  const char* text = R"([model]
name = "gyrostat"
[model.body.carrier]
kind = "spatial"
mass = 3.0
inertia = [0.2, 0.3, 0.4]
markers = { bearing = { at = [0.1, 0.0, 0.2], axis = [1, 1, 0], angle = 0.7 } }
[model.body.rotor]
kind = "spatial"
mass = 1.0
inertia = [0.02, 0.02, 0.03]
com = [0, 0, 0.05]
markers = { rim = [0.15, 0.0, 0.05] }
[model.joint.axle]
type = "revolute"
body1 = "carrier"
marker1 = "bearing"
body2 = "rotor"
coordinates = ["psi"]
[model.outputs]
vx = "rotor_rim_vx"
vy = "rotor_rim_vy"
vz = "rotor_rim_vz"
ax = "rotor_rim_ax"
ay = "rotor_rim_ay"
az = "rotor_rim_az"
wx = "rotor_wx"
wy = "rotor_wy"
alx = "rotor_alphax"
aly = "rotor_alphay"
)";
  const auto desc = load_model_text(text, "gyrostat.toml");
  const auto model = desc->instantiate({});
  BOOST_REQUIRE_EQUAL(model->n(), 8);
  Vector4d e(0.9, 0.2, -0.3, 0.1);
  e.normalize();
  Eigen::VectorXd q0(8), qd0(8);
  q0 << 1000, -500, 200, e, 0.4;
  qd0 << 0.5, -0.2, 0.1, 0.5 * E_of(e).transpose() * Vector3d(1.0, -2.0, 1.5), 20.0;
  mech::SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = 1e-12;
  o.atol = 1e-12;
  o.active_constraints = all_constraints(*model);
  const auto& names = model->derived_names();
  auto col = [&](const std::string& n) { return static_cast<int>(std::find(names.begin(), names.end(), n) - names.begin()); };
  const std::vector<std::pair<int, int>> pairs{{col("vx"), col("ax")}, {col("vy"), col("ay")}, {col("vz"), col("az")},
                                               {col("wx"), col("alx")}, {col("wy"), col("aly")}};
  const double h = 1e-3;
  std::vector<std::vector<double>> V(pairs.size()), Acc(pairs.size());
  int next = 0;
  const auto r = mech::simulate(*model, q0, qd0, o, [&](const mech::StepView& view) {
    while (next * h <= view.t + 1e-12 && next * h <= o.t_end) {
      const mech::Sample& s = view.sample(std::min(next * h, view.t));
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        V[k].push_back(s.derived[pairs[k].first]);
        Acc[k].push_back(s.derived[pairs[k].second]);
      }
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  double worst = 0, scale = 0;
  int points = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto& v = V[k];
    const auto& a = Acc[k];
    std::vector<double> add(v.size(), 0.0);
    for (std::size_t i = 1; i + 1 < v.size(); ++i) add[i] = std::abs(a[i + 1] - 2 * a[i] + a[i - 1]) / (h * h);
    for (std::size_t i = 2; i + 2 < v.size(); ++i) {
      const double err = std::abs(a[i] - (v[i + 1] - v[i - 1]) / (2 * h));
      const double allowed = 1.5 * h * h / 6 * std::max({add[i - 1], add[i], add[i + 1]}) + 1e-8 / h + 1e-9 * std::abs(a[i]);
      if (err > allowed) BOOST_ERROR("pair " << k << " at t = " << i * h << ": " << err << " > " << allowed);
      worst = std::max(worst, err);
      scale = std::max(scale, std::abs(a[i]));
      ++points;
    }
  }
  BOOST_TEST_MESSAGE("worst |a - central difference of v| " << worst << " of accelerations up to " << scale
                                                            << ", " << points << " points");
  BOOST_TEST(points > 4900);
  BOOST_TEST(scale > 10.0);
}

// ---- Spatial bushings (issue 22, BSH; docs/bodies-spatial.md "Bushings") --------------------
//
// The rotational measure of a bushing between marker frames E1, E2 (in ground) is
// θ = vee(A − Aᵀ)/√(1 + tr A) with A = E1ᵀ E2, i.e. 2 sin(φ/2) n for the rotation by φ about n
// (marker1 axes); V = ½ Σ k_i θ_i² = Σ k_i (1 − cos φ) n_i², for a turn about marker axis i
// exactly k_i (1 − cos φ): a pendulum's potential, J φ̈ = −k_i sin φ.

namespace {

// The energy-form texts the body form generated (T and V as pcsim derives them), appended as
// outputs `T_model`, `V_model` to the body model: the numbers the model's own potential gives.
std::string with_energy_outputs(const std::string& text, const std::string& file) {
  const detail::ModelSource src = detail::parse_model_source_text(text, file);
  return text + "[model.outputs]\nT_model = \"" + src.kinetic.text + "\"\nV_model = \"" +
         src.potential.text + "\"\n";
}

int output_index(const mech::Model& m, const std::string& name) {
  const auto& names = m.derived_names();
  const auto it = std::find(names.begin(), names.end(), name);
  BOOST_REQUIRE_MESSAGE(it != names.end(), "no output " << name);
  return static_cast<int>(it - names.begin());
}

// A body on a bushing to ground. The body frame's origin is at (X0, Y0, Z0) far from the ground
// origin; its centre of mass and the bushing's marker `c` are offset from it by (cx, cy, cz),
// and ground's marker `seat` is where `c` is when the body frame is aligned with ground. So the
// bushing is unloaded at e = (1, 0, 0, 0), r = (X0, Y0, Z0), and a turn about a principal axis
// through the centre of mass leaves the marker where it is.
std::string bushed_body(const std::string& gravity = "0", const std::string& com = "[\"cx\", \"cy\", \"cz\"]") {
  return R"([model]
name = "bushed"
[model.parameters]
X0 = 1000.0
Y0 = -2000.0
Z0 = 500.0
cx = 0.3
cy = -0.2
cz = 0.1
m = 5.0
J1 = 0.1
J2 = 0.2
J3 = 0.3
kt = 1e5
k1 = 40.0
k2 = 90.0
k3 = 160.0
ct = 0.0
c1 = 0.0
c2 = 0.0
c3 = 0.0
g = )" + gravity + R"(
[model.body.ground]
markers = { seat = ["X0 + cx", "Y0 + cy", "Z0 + cz"] }
[model.body.b]
kind = "spatial"
mass = "m"
com = )" + com + R"(
inertia = ["J1", "J2", "J3"]
markers = { c = ["cx", "cy", "cz"] }
[model.force.mount]
type = "bushing"
marker1 = "seat"
body2 = "b"
marker2 = "c"
stiffness = ["kt", "kt", "kt"]
damping = ["ct", "ct", "ct"]
rotational_stiffness = ["k1", "k2", "k3"]
rotational_damping = ["c1", "c2", "c3"]
[model.force.weight]
type = "gravity"
g = [0, 0, "-g"]
)";
}

}  // namespace

// Small rotations: a body turned about one principal axis through its centre of mass (the
// bushing's centre) oscillates as J_i φ̈ = −k_i sin φ, at ω = √(k_i/J_i) for small φ. From
// rest at φ0 = 1e-3 rad, the period is measured from the downward zero crossings of the output mount_th_i (located by bisection on
// the dense output) over 6 periods. The amplitude lengthens the pendulum's period by the factor
// 1 + φ0²/16 + 11 φ0⁴/3072 (= 1 + 6.25e-8 + 4e-15), so the measured period must equal
// 2π √(J_i/k_i) (1 + φ0²/16) to 1e-9 relative (the integration at rtol 1e-11 and the bisection
// locate the crossings to ~1e-11 s; measured 1e-10 to 4e-10), and 2π √(J_i/k_i) alone to
// 1e-7; the other two components of θ stay below 1e-12 (no coupling about principal axes). For
// each axis, with the body 2.3 km from the ground origin.
BOOST_AUTO_TEST_CASE(bushing_turned_about_one_axis_oscillates_at_sqrt_k_over_J) {
  std::string text = bushed_body();
  text += "[model.outputs]\nth1 = \"mount_th1\"\nth2 = \"mount_th2\"\nth3 = \"mount_th3\"\n";
  const auto desc = load_model_text(text, "bushed.toml");
  const auto model = desc->instantiate({});
  const Vector3d J(0.1, 0.2, 0.3), k(40, 90, 160);
  const double phi0 = 1e-3;
  for (int axis = 0; axis < 3; ++axis) {
    const double w = std::sqrt(k[axis] / J[axis]), period = 2 * M_PI / w;
    Vector4d e(std::cos(phi0 / 2), 0, 0, 0);
    e[1 + axis] = std::sin(phi0 / 2);
    // The body frame turned by φ0 about axis i through the centre of mass c (body frame), which
    // stays at P_c = (X0, Y0, Z0) + c: the origin at r = P_c − A(e) c.
    const Vector3d c(0.3, -0.2, 0.1), Pc = Vector3d(1000, -2000, 500) + c;
    const State s0 = body_state(Pc - A_of(e) * c, e, Vector3d::Zero(), Vector3d::Zero());
    mech::SimulationOptions o;
    o.t_end = 6.25 * period;
    o.rtol = o.atol = 1e-11;
    o.kernel = Kernel::cpp;
    o.active_constraints = all_constraints(*model);
    const int i_th = output_index(*model, "th" + std::to_string(axis + 1));
    std::vector<double> crossings;
    double off_axis = 0;
    const mech::SimulationResult r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
      const mech::Sample a = v.at(v.t_prev), b = v.at(v.t);
      for (int j = 0; j < 3; ++j)
        if (j != axis) off_axis = std::max(off_axis, std::abs(b.derived[output_index(*model, "th" + std::to_string(j + 1))]));
      if (a.derived[i_th] > 0 && b.derived[i_th] <= 0) {
        double lo = v.t_prev, hi = v.t;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (v.at(mid).derived[i_th] > 0 ? lo : hi) = mid;
        }
        crossings.push_back(0.5 * (lo + hi));
      }
      return true;
    });
    BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
    BOOST_REQUIRE_GE(crossings.size(), 6u);
    const double measured = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
    const double rel = std::abs(measured - period) / period;
    const double rel_corrected = std::abs(measured - period * (1 + phi0 * phi0 / 16)) / period;
    BOOST_TEST_MESSAGE("axis " << axis + 1 << ": period " << measured << " s, 2 pi sqrt(J/k) = " << period
                               << " s, relative " << rel << " (amplitude effect phi0^2/16 = "
                               << phi0 * phi0 / 16 << "; after it " << rel_corrected << "); off-axis |theta| " << off_axis);
    BOOST_TEST(rel < 1e-7);
    BOOST_TEST(rel_corrected < 1e-9);
    BOOST_TEST(off_axis < 1e-12);
  }
}

// Two free spatial bodies whose markers p (on a) and q (on b) are turned about skew axes, joined
// by a bushing `mount` with the coefficient line `coefficients`.
namespace {
std::string two_bodies_with_bushing(const std::string& coefficients) {
  return R"([model]
name = "two_bodies"
[model.body.a]
kind = "spatial"
mass = 1.0
inertia = [0.1, 0.2, 0.25]
markers = { p = { at = [0.1, 0.2, 0.3], axis = [1, 2, 3], angle = 0.7 } }
[model.body.b]
kind = "spatial"
mass = 2.0
inertia = [0.3, 0.2, 0.4]
markers = { q = { at = [-0.2, 0.1, 0.05], axis = [-2, 1, 0.5], angle = -1.9 } }
[model.force.mount]
type = "bushing"
body1 = "a"
marker1 = "p"
body2 = "b"
marker2 = "q"
)" + coefficients + "\n";
}
}  // namespace

// The measure against an independent formula: two spatial bodies (neither ground) with markers
// turned about skew axes; at 200 random orientations (rotations closer than 0.05 rad to a half
// turn skipped: the measure is not defined there) the model's potential V (the text pcsim
// derives from, evaluated as an output) equals ½ Σ k_i (2 sin(φ/2) n_i)², φ and n (marker1 axes)
// extracted from E1ᵀ E2 by Eigen's AngleAxis (E = A(e) R_marker, R from Eigen's AngleAxis of the
// markers' axis and angle), and mount_th1..3 equal 2 sin(φ/2) n: to 1e-12 (of k_max).
BOOST_AUTO_TEST_CASE(bushing_measure_equals_two_sin_half_angle_times_axis_at_random_orientations) {
  const std::string body_text = two_bodies_with_bushing("rotational_stiffness = [3.0, 5.0, 7.0]");
  const std::string text = with_energy_outputs(body_text, "two_bodies.toml") +
                           "th1 = \"mount_th1\"\nth2 = \"mount_th2\"\nth3 = \"mount_th3\"\n";
  const auto model = load_model_text(text, "two_bodies.toml")->instantiate({});
  BOOST_REQUIRE_EQUAL(model->n(), 14);
  const int iV = output_index(*model, "V_model"), i1 = output_index(*model, "th1");
  const Matrix3d R1 = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Matrix3d R2 = Eigen::AngleAxisd(-1.9, Vector3d(-2, 1, 0.5).normalized()).toRotationMatrix();
  const Vector3d k(3, 5, 7);
  std::mt19937 rng(2022);
  double worst_V = 0, worst_th = 0, max_phi = 0;
  int used = 0;
  while (used < 200) {
    Vector4d ea(uniform(rng), uniform(rng), uniform(rng), uniform(rng)), eb(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
    ea.normalize();
    eb.normalize();
    const Matrix3d A = (A_of(ea) * R1).transpose() * (A_of(eb) * R2);
    const Eigen::AngleAxisd aa(A);
    if (aa.angle() > M_PI - 0.05) continue;
    const Vector3d th = 2 * std::sin(aa.angle() / 2) * aa.axis();
    const double V = 0.5 * k.dot(th.cwiseProduct(th));
    Eigen::VectorXd q(14), qd = Eigen::VectorXd::Zero(14);
    q << 10 * uniform(rng), 10 * uniform(rng), 10 * uniform(rng), ea, 10 * uniform(rng), 10 * uniform(rng), 10 * uniform(rng), eb;
    const Eigen::VectorXd out = outputs_at(*model, q, qd);
    worst_V = std::max(worst_V, std::abs(out[iV] - V) / k.maxCoeff());
    for (int i = 0; i < 3; ++i) worst_th = std::max(worst_th, std::abs(out[i1 + i] - th[i]));
    max_phi = std::max(max_phi, aa.angle());
    ++used;
  }
  BOOST_TEST_MESSAGE("200 orientations (largest angle " << max_phi << " rad): worst |V - V_axis_angle|/k_max "
                     << worst_V << ", worst |theta - 2 sin(phi/2) n| " << worst_th);
  BOOST_TEST(worst_V < 1e-12);
  BOOST_TEST(worst_th < 1e-12);
}

// The damping: between two spatial bodies with turned markers and rotational damping only, the
// power of the generalized forces Q·q̇ = −2F (F is quadratic in q̇) must equal
// −Σ c_i (e1_i·(ω2 − ω1))² with e1_i marker1's axes in ground (A(e) R1, R1 from Eigen's
// AngleAxis) and ω the bodies' angular velocities in ground, at 100 random states: to 1e-12 of
// Σ c_i |ω2 − ω1|² (rounding). So the coefficients act about marker1's axes, not body or ground
// axes, and on the relative angular velocity.
BOOST_AUTO_TEST_CASE(bushing_damping_dissipates_c_times_relative_angular_velocity_squared_in_marker1_axes) {
  const std::string text = two_bodies_with_bushing("rotational_damping = [0.3, 0.5, 0.7]");
  const auto model = load_model_text(text, "two_bodies.toml")->instantiate({});
  const Matrix3d R1 = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Vector3d c(0.3, 0.5, 0.7);
  std::mt19937 rng(7);
  double worst = 0;
  for (int k = 0; k < 100; ++k) {
    Vector4d ea(uniform(rng), uniform(rng), uniform(rng), uniform(rng)), eb(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
    ea.normalize();
    eb.normalize();
    const Vector3d wa(3 * uniform(rng), 3 * uniform(rng), 3 * uniform(rng)), wb(3 * uniform(rng), 3 * uniform(rng), 3 * uniform(rng));
    const State sa = body_state(Vector3d(5 * uniform(rng), 5 * uniform(rng), 5 * uniform(rng)), ea,
                                Vector3d(uniform(rng), uniform(rng), uniform(rng)), wa);
    const State sb = body_state(Vector3d(5 * uniform(rng), 5 * uniform(rng), 5 * uniform(rng)), eb,
                                Vector3d(uniform(rng), uniform(rng), uniform(rng)), wb);
    Eigen::VectorXd q(14), qd(14), Q(14);
    q << sa.q, sb.q;
    qd << sa.qd, sb.qd;
    model->forces(0.0, q, qd, Q);
    const Vector3d wr = (A_of(ea) * R1).transpose() * (wb - wa);
    const double expected = -c.dot(wr.cwiseProduct(wr));
    worst = std::max(worst, std::abs(Q.dot(qd) - expected) / (c.sum() * (wb - wa).squaredNorm()));
  }
  BOOST_TEST_MESSAGE("worst |Q.qd + sum c_i wr_i^2| / (sum c |w2 - w1|^2): " << worst);
  BOOST_TEST(worst < 1e-12);
}

// Static equilibrium under gravity (−z): the bushing's centre `c` at the body frame's origin,
// the centre of mass l = 0.2 m along the body's x. The translational springs carry the weight:
// the origin sags by m g / kt; the rotational spring about y carries the moment m g l cos φ:
// V = k2 (1 − cos φ) − m g l sin φ is stationary at tan φ = m g l / k2 (a turn by φ about +y
// lowers the centre of mass by l sin φ). At that closed-form state q̈ = 0 to 1e-8 m/s² (the
// spring's stretch is z − Z0 at z = 500 m: its rounding, ε 500 m = 1.1e-13 m, times kt/m = 2e4
// 1/s² gives 2e-9 m/s²; measured 6e-10), and a damped run from the unloaded pose settles there
// (to 1e-9 m and 1e-9 rad after 20 s).
BOOST_AUTO_TEST_CASE(bushing_holds_a_body_under_gravity_at_the_closed_form_sag_and_turn) {
  std::string text = bushed_body("9.81", "[0.2, 0, 0]");
  // The marker and the seat at the body frame's origin (cx = cy = cz = 0).
  text.replace(text.find("cx = 0.3\ncy = -0.2\ncz = 0.1\n"), std::string("cx = 0.3\ncy = -0.2\ncz = 0.1\n").size(),
               "cx = 0.0\ncy = 0.0\ncz = 0.0\n");
  const auto desc = load_model_text(text, "bushed.toml");
  const double m = 5, g = 9.81, l = 0.2, kt = 1e5, k2 = 90;
  const double sag = m * g / kt, phi = std::atan(m * g * l / k2);
  const Vector4d e(std::cos(phi / 2), 0, std::sin(phi / 2), 0);
  const State eq = body_state(Vector3d(1000, -2000, 500 - sag), e, Vector3d::Zero(), Vector3d::Zero());
  {
    const auto model = desc->instantiate({});
    mech::Dynamics dyn(*model, Kernel::cpp);
    const auto set = mech::ActiveSet::of(*model, {0});
    BOOST_REQUIRE(dyn.evaluate(set, 0.0, eq.q, eq.qd) == mech::ModelIssue::none);
    BOOST_REQUIRE(dyn.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
    BOOST_TEST_MESSAGE("at sag " << sag << " m, phi " << phi << " rad: max |q_dd| " << dyn.qdd.cwiseAbs().maxCoeff());
    BOOST_TEST(dyn.qdd.cwiseAbs().maxCoeff() < 1e-8);
  }
  // Damped (critically-ish: ct = 1400 N s/m, c2 = 8 N m s/rad), from the unloaded pose.
  const auto damped = desc->instantiate({{"ct", 1400.0}, {"c1", 8.0}, {"c2", 8.0}, {"c3", 8.0}});
  const State s0 = body_state(Vector3d(1000, -2000, 500), Vector4d(1, 0, 0, 0), Vector3d::Zero(), Vector3d::Zero());
  mech::SimulationOptions o;
  o.t_end = 20.0;
  o.rtol = o.atol = 1e-11;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_constraints(*damped);
  Eigen::VectorXd q_end;
  const mech::SimulationResult r = mech::simulate(*damped, s0.q, s0.qd, o, [&](const mech::StepView& v) {
    q_end = v.at(v.t).q;
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  const Vector4d e_end = q_end.segment<4>(3);
  const double phi_end = 2 * std::atan2(e_end[2], e_end[0]);
  BOOST_TEST_MESSAGE("after 20 s: sag " << 500 - q_end[2] << " m (minus the closed form: " << (500 - q_end[2]) - sag
                     << " m), turn " << phi_end << " rad (minus the closed form: " << phi_end - phi << " rad), x, y drift " << std::abs(q_end[0] - 1000) << ", "
                     << std::abs(q_end[1] + 2000) << ", e1, e3 " << e_end[1] << ", " << e_end[3]);
  BOOST_TEST(std::abs((500 - q_end[2]) - sag) < 1e-9);
  BOOST_TEST(std::abs(phi_end - phi) < 1e-9);
  BOOST_TEST(std::abs(q_end[0] - 1000) < 1e-9);
  BOOST_TEST(std::abs(q_end[1] + 2000) < 1e-9);
  BOOST_TEST(std::abs(e_end[1]) + std::abs(e_end[3]) < 1e-9);
}

// Energy: the body on the bushing (translational and rotational springs, gravity) started at
// the unloaded pose with angular velocity ω = (2, −3, 4) rad/s and origin velocity
// v = (0.1, 0.2, −0.3) m/s (it tumbles up to ~0.3 rad from the rest pose). T + V are the model's
// own texts as outputs T_model, V_model; V holds m g z_c ≈ 2.5e4 J at z = 500 m, so the scale is
// T0 = ½ m |v + ω × c|² + ½ ωᵀ J ω = 8.1 J (checked), not E0. Undamped over 3 s at rtol 1e-11:
// |E − E0| < 1e-7 T0. Radau's own numerical dissipation loses energy steadily: measured
// 7.0e-6, 1.1e-6, 1.7e-7, 2.8e-8 J at rtol 1e-9 ... 1e-12, the integrator's error, shrinking
// with rtol. Damped (ct = 50 N s/m, c = 0.05 N m s/rad): E never rises from one accepted step to
// the next by more than 1e-9 T0 (E's rounding at 2.5e4 J is ~1e-11 J; measured: never rises) and
// falls by more than 0.5 T0 over the run (measured 6.2 J).
BOOST_AUTO_TEST_CASE(bushing_conserves_energy_undamped_and_loses_it_monotonically_damped) {
  const std::string text = with_energy_outputs(bushed_body("9.81"), "bushed.toml");
  const auto desc = load_model_text(text, "bushed.toml");
  const Vector3d v0(0.1, 0.2, -0.3), w0(2, -3, 4), c(0.3, -0.2, 0.1), J(0.1, 0.2, 0.3);
  const State s0 = body_state(Vector3d(1000, -2000, 500), Vector4d(1, 0, 0, 0), v0, w0);
  BOOST_REQUIRE_CLOSE(0.5 * 5.0 * (v0 + w0.cross(c)).squaredNorm() + 0.5 * w0.dot(J.cwiseProduct(w0)), 8.1, 1e-12);
  for (bool damped : {false, true}) {
    const auto model = damped ? desc->instantiate({{"ct", 50.0}, {"c1", 0.05}, {"c2", 0.05}, {"c3", 0.05}})
                              : desc->instantiate({});
    const int iT = output_index(*model, "T_model"), iV = output_index(*model, "V_model");
    mech::SimulationOptions o;
    o.t_end = 3.0;
    o.rtol = o.atol = 1e-11;
    o.kernel = Kernel::cpp;
    o.active_constraints = all_constraints(*model);
    double E0 = NAN, T0 = NAN, drift = 0, rise = 0, E_last = NAN;
    int steps = 0;
    const mech::SimulationResult r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
      if (std::isnan(E0)) {
        const mech::Sample s = v.at(v.t_prev);
        T0 = s.derived[iT];
        E0 = E_last = s.derived[iT] + s.derived[iV];
      }
      const mech::Sample s = v.at(v.t);
      const double E = s.derived[iT] + s.derived[iV];
      drift = std::max(drift, std::abs(E - E0));
      rise = std::max(rise, E - E_last);
      E_last = E;
      ++steps;
      return true;
    });
    BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
    BOOST_TEST_MESSAGE((damped ? "damped" : "undamped") << ": T0 " << T0 << " J, " << steps << " steps, max |E - E0| "
                       << drift << " J, E0 - E_end " << E0 - E_last << " J, largest rise between steps " << rise << " J");
    BOOST_TEST(std::abs(T0 - 8.1) < 1e-12);
    if (!damped) {
      BOOST_TEST(drift < 1e-7 * T0);
    } else {
      BOOST_TEST(rise < 1e-9 * T0);
      BOOST_TEST(E0 - E_last > 0.5 * T0);
    }
  }
}

// At a half turn (1 + tr A = 0) the measure is 0/0: the evaluation reports a non-finite
// generalized force (the engine's exit-3 path), never a number. Near it, 1 + tr A = 4 sin²(δ/2)
// ≈ δ² at δ from the half turn, and the measure's rounding grows as ε/δ²: V of the model (its
// own text, translational springs off) against ½ Σ k_i (2 sin(φ/2) n_i)² at δ = 1e-1 ... 1e-6
// rad about a skew axis, to 10 ε k_max/δ² (measured: printed).
BOOST_AUTO_TEST_CASE(bushing_at_a_half_turn_gives_a_non_finite_force_not_a_number) {
  const auto desc = load_model_text(with_energy_outputs(bushed_body(), "bushed.toml"), "bushed.toml");
  const auto model = desc->instantiate({});
  mech::Dynamics dyn(*model, Kernel::cpp);
  const auto set = mech::ActiveSet::of(*model, {0});
  for (int axis = 0; axis < 3; ++axis) {
    Vector4d e(0, 0, 0, 0);
    e[1 + axis] = 1;  // a half turn about a body axis
    const State s = body_state(Vector3d(1000, -2000, 500), e, Vector3d::Zero(), Vector3d::Zero());
    BOOST_TEST((dyn.evaluate(set, 0.0, s.q, s.qd) == mech::ModelIssue::non_finite));
  }
  const auto no_springs = desc->instantiate({{"kt", 0.0}});
  const int iV = output_index(*no_springs, "V_model");
  const Vector3d k(40, 90, 160), n = Vector3d(1, 2, 2) / 3;
  for (double delta : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    const double phi = M_PI - delta;
    Vector4d e;
    e << std::cos(phi / 2), std::sin(phi / 2) * n;
    const State s = body_state(Vector3d(1000, -2000, 500), e, Vector3d::Zero(), Vector3d::Zero());
    Eigen::VectorXd out(static_cast<Eigen::Index>(no_springs->derived_names().size()));
    no_springs->derived(0.0, s.q, s.qd, Eigen::VectorXd::Zero(7), Eigen::VectorXd::Zero(7), out);
    const Vector3d th = 2 * std::sin(phi / 2) * n;
    const double V = 0.5 * k.dot(th.cwiseProduct(th)), err = std::abs(out[iV] - V) / k.maxCoeff();
    const double bound = 10 * std::numeric_limits<double>::epsilon() / (delta * delta);
    BOOST_TEST_MESSAGE("delta " << delta << " rad from the half turn: |V - V_exact|/k_max " << err << " (bound " << bound << ")");
    BOOST_TEST(err < bound);
  }
}
