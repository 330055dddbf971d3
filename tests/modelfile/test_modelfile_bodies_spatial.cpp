// Spatial bodies and joints in the body form (docs/bodies-spatial.md), against oracles that are
// not the expansion itself:
// - the heavy top, the rolling coin and the tumbling body written as bodies give the same q_dd
//   and R as the energy-form models (models/top_heavy.toml, ... , whose oracles are in
//   test_modelfile_spatial_bodies.cpp) at random states;
// - the spherical joint's reaction, in its own (rotated) frame, is Newton's m a_c + m g for the
//   top in steady precession (closed form);
// - each spatial joint type removes exactly the relative motions its definition says (the
//   twists of the joint frame: allowed ones satisfy every row, each forbidden one violates one),
//   with the rank of its rows;
// - a prismatic joint between spatial bodies (a bead on a spun rod), as a tree joint and as rows,
//   follows the closed form s0 cosh(w t), with the drive's torque and the rows' reaction;
// - a wheel on an accelerating deck rolls, relative to the deck, as on a fixed plane under the
//   gravity of the deck's frame (the wheel joint's moving-plane rows);
// - a wheel rolling on a sphere (inside a bowl, or outside) in a vertical plane follows the
//   reduced pendulum equation with its contact force; out of the plane, its contact point is the
//   rim's farthest point found by search, it does not slip there, and the energy is constant;
// - the 2-D Coulomb cone's rows (a point_on_plane with mu_static, on ground and on a moving
//   body; a rolling wheel with mu_static, on a plane and on a sphere) are the contact's two
//   Coulomb rows and equal the closed-form sliding velocity along orthonormal tangents;
// - the ball joint's rows (a sphere on a plane, on ground and on a tumbling deck) equal their
//   definition computed with Eigen, its reaction acts at the contact point; a ball rolling on a
//   driven turntable circles at 2/7 of the table's rate (the closed form dv/dt = (2/7) Omega z x v);
// - the ball joint on a sphere (outside, inside a bowl; on ground and on a tumbling deck): its
//   rows and reaction equal their definition computed with Eigen (tangents by Eigen's
//   FromTwoVectors); a ball rolling in a bowl oscillates at w^2 = 5 g / (7 (Rb - r)), its period's
//   excess the pendulum's th0^2/16, its energy constant;
// - inertia tensors that are not symmetric or not positive definite are rejected naming the key;
// - the Whipple bicycle as bodies (models/whipple_bodies.toml) conserves energy in a nonlinear
//   run and, between its weave and capsize speeds, rights itself after a push in roll, while
//   below the weave speed it does not.
#define BOOST_TEST_MODULE modelfile_bodies_spatial
#include <boost/test/unit_test.hpp>
#include "common/eigen_instances.hpp"

#include <chrono>
#include <fstream>
#include <cmath>
#include <sstream>

#include "common/eigen_instances.hpp"

#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"
#include "../support/pendulum_rk4.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::Vector4d;

namespace {

Eigen::Matrix<double, 3, 4> E_of(const Vector4d& e) {
  Eigen::Matrix<double, 3, 4> E;
  E << -e[1], e[0], -e[3], e[2], -e[2], e[3], e[0], -e[1], -e[3], -e[2], e[1], e[0];
  return E;
}
Eigen::Matrix<double, 3, 4> G_of(const Vector4d& e) {
  Eigen::Matrix<double, 3, 4> G;
  G << -e[1], e[0], e[3], -e[2], -e[2], -e[3], e[0], e[1], -e[3], e[2], -e[1], e[0];
  return G;
}
Matrix3d A_of(const Vector4d& e) { return E_of(e) * G_of(e).transpose(); }
Vector4d e_of_axis_angle(const Vector3d& axis, double angle) {
  const Vector3d u = axis.normalized();
  return Vector4d(std::cos(angle / 2), u[0] * std::sin(angle / 2), u[1] * std::sin(angle / 2),
                  u[2] * std::sin(angle / 2));
}
// Euler parameters of a rotation matrix (Shepperd's choice of the largest component).
Vector4d e_of_matrix(const Matrix3d& A) {
  const double tr = A.trace();
  Vector4d e;
  const double c[4] = {1 + tr, 1 + 2 * A(0, 0) - tr, 1 + 2 * A(1, 1) - tr, 1 + 2 * A(2, 2) - tr};
  int k = 0;
  for (int i = 1; i < 4; ++i)
    if (c[i] > c[k]) k = i;
  const double s = 0.5 * std::sqrt(c[k]);
  e[k] = s;
  const double f = 0.25 / s;
  if (k == 0) e << s, (A(2, 1) - A(1, 2)) * f, (A(0, 2) - A(2, 0)) * f, (A(1, 0) - A(0, 1)) * f;
  if (k == 1) e << (A(2, 1) - A(1, 2)) * f, s, (A(0, 1) + A(1, 0)) * f, (A(0, 2) + A(2, 0)) * f;
  if (k == 2) e << (A(0, 2) - A(2, 0)) * f, (A(0, 1) + A(1, 0)) * f, s, (A(1, 2) + A(2, 1)) * f;
  if (k == 3) e << (A(1, 0) - A(0, 1)) * f, (A(0, 2) + A(2, 0)) * f, (A(1, 2) + A(2, 1)) * f, s;
  return e;
}

std::vector<int> all_rows(const mech::Model& m) {
  std::vector<int> r;
  for (int i = 0; i < static_cast<int>(m.constraints().size()); ++i) r.push_back(i);
  return r;
}
std::vector<std::string> all_names(const mech::Model& m) {
  std::vector<std::string> r;
  for (const auto& c : m.constraints()) r.push_back(c.name);
  return r;
}
const char* kTopBodies = R"(
[model]
name = "top_bodies"
[model.parameters]
m = 1.0
J1 = 0.005
J3 = 0.008
l = 0.1
g = 9.81
X0 = 0.0
Y0 = 0.0
Z0 = 0.0
psi_j = 0.0
[model.body.ground.markers]
pivot = { at = ["X0", "Y0", "Z0"], axis = [0, 0, 1], angle = "psi_j" }
[model.body.top]
kind = "spatial"
mass = "m"
inertia = ["J1", "J1", "J3"]
markers.tip = [0, 0, "-l"]
[model.joint.tip]
type = "spherical"
body1 = "ground"
marker1 = "pivot"
body2 = "top"
marker2 = "tip"
[model.force.gravity]
type = "gravity"
g = [0, 0, "-g"]
)";

const char* kCoinBodies = R"(
[model]
name = "coin_bodies"
[model.parameters]
coin_m = 0.1
r = 0.05
g = 9.81
[model.body.ground.markers]
plane = [0, 0, 0]
[model.body.coin]
kind = "spatial"
mass = "coin_m"
inertia = ["coin_m*r^2/4", "coin_m*r^2/4", "coin_m*r^2/2"]
[model.joint.roll]
type = "wheel"
body1 = "ground"
marker1 = "plane"
body2 = "coin"
marker2 = "origin"
radius = "r"
[model.force.gravity]
type = "gravity"
g = [0, 0, "-g"]
)";

const char* kTumblingBodies = R"(
[model]
name = "tumbling_bodies"
[model.body.b]
kind = "spatial"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
)";

// Random states with |e| = 1 (positions near `centre`, velocities random).
struct State {
  Eigen::VectorXd q, qd;
};
State random_state(std::mt19937& rng, int n, const Vector3d& centre) {
  State s;
  s.q = Eigen::VectorXd::Zero(n);
  s.qd = Eigen::VectorXd::Zero(n);
  Vector4d e(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
  e.normalize();
  s.q.head<3>() = centre + 0.1 * Vector3d(uniform(rng), uniform(rng), uniform(rng));
  s.q.segment<4>(3) = e;
  for (int i = 0; i < n; ++i) s.qd[i] = uniform(rng);
  s.qd.segment<4>(3) -= e * e.dot(s.qd.segment<4>(3));  // e . e_d = 0
  return s;
}

}  // namespace

// The body form expands to the energy form's mechanics: at 20 random states of each, the
// accelerations and reactions of the body-form top (its joint frame turned by 0.7 rad: the rows
// differ, their span does not), coin and tumbling body equal those of models/top_heavy.toml,
// rolling_coin.toml and tumbling_body.toml to 1e-10 relative (rounding of two different
// expression trees).
BOOST_AUTO_TEST_CASE(spatial_bodies_give_the_energy_form_models_mechanics) {
  struct Pair {
    const char* text;
    const char* file;
    std::map<std::string, double> body_params, energy_params;
  };
  const std::vector<Pair> pairs{
      {kTopBodies, "top_heavy.toml", {{"psi_j", 0.7}, {"X0", 3.0}, {"Y0", -2.0}, {"Z0", 1.0}},
       {{"X0", 3.0}, {"Y0", -2.0}, {"Z0", 1.0}}},
      {kCoinBodies, "rolling_coin.toml", {}, {}},
      {kTumblingBodies, "tumbling_body.toml", {}, {}}};
  std::mt19937 rng(7);
  for (const auto& p : pairs) {
    const auto bd = load_model_text(p.text, "test.toml");
    const auto ed = load_model_file(model_path(p.file));
    BOOST_REQUIRE(bd->coordinates() == ed->coordinates());
    const auto bm = bd->instantiate(p.body_params), em = ed->instantiate(p.energy_params);
    mech::Dynamics db(*bm, Kernel::cpp), de(*em, Kernel::cpp);
    const auto sb = mech::ActiveSet::of(*bm, all_rows(*bm)), se = mech::ActiveSet::of(*em, all_rows(*em));
    BOOST_REQUIRE(sb.size() == se.size());
    double worst = 0;
    for (int k = 0; k < 20; ++k) {
      const State s = random_state(rng, bm->n(), Vector3d(3.0, -2.0, 1.0));
      BOOST_REQUIRE(db.evaluate(sb, 0.0, s.q, s.qd) == mech::ModelIssue::none);
      BOOST_REQUIRE(db.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
      BOOST_REQUIRE(de.evaluate(se, 0.0, s.q, s.qd) == mech::ModelIssue::none);
      BOOST_REQUIRE(de.solve(mech::ReactionMethod::compatibility) == mech::ModelIssue::none);
      worst = std::max({worst, rel_diff(db.qdd, de.qdd, 1.0), rel_diff(db.R, de.R, 1.0)});
    }
    BOOST_TEST_MESSAGE(p.file << ": body form vs energy form, max relative difference of q_dd, R: " << worst);
    BOOST_TEST(worst < 1e-10);
  }
}

// The top in steady precession (as in test_modelfile_spatial_bodies: theta = 0.5, spin 40
// rad/s) with its spherical joint's frame turned by psi_j = 0.7 rad about z: the reaction on the
// top at the tip is F = m a_c + m g z (Newton; a_c the centre of mass's centripetal acceleration
// Omega^2 l sin(theta) towards the axis), and F_tip_x, _y, _z are its components in the joint
// frame, Rz(psi_j)^T F, to 1e-6 N over two precession turns; the moment about the tip is 0.
BOOST_AUTO_TEST_CASE(spherical_joint_reaction_is_newtons_force_in_the_joint_frame) {
  const auto desc = load_model_text(kTopBodies, "top_bodies.toml");
  const double psi_j = 0.7;
  const Vector3d P(500, -300, 100);
  const auto model = desc->instantiate({{"psi_j", psi_j}, {"X0", P[0]}, {"Y0", P[1]}, {"Z0", P[2]}});
  const double m = 1.0, l = 0.1, g = 9.81, J1 = 0.005, J3 = 0.008, theta = 0.5, w3 = 40.0;
  const double I1 = J1 + m * l * l, a = I1 * std::cos(theta), bq = -J3 * w3, c = m * g * l;
  const double Omega = (-bq - std::sqrt(bq * bq - 4 * a * c)) / (2 * a);
  const Vector4d e0 = e_of_axis_angle(Vector3d::UnitX(), theta);
  const Vector3d k0(0, -std::sin(theta), std::cos(theta));
  const Vector3d w = Omega * Vector3d::UnitZ() + (w3 - Omega * std::cos(theta)) * k0;
  Eigen::VectorXd q(7), qd(7);
  q << P + l * k0, e0;
  qd << w.cross(l * k0), 0.5 * E_of(e0).transpose() * w;
  const int fx = output_index(*desc, "F_tip_x");
  const int mx = output_index(*desc, "M_tip_x");
  const Matrix3d Rj = Eigen::AngleAxisd(psi_j, Vector3d::UnitZ()).toRotationMatrix();
  mech::SimulationOptions o;
  o.t_end = 2 * 2 * M_PI / Omega;
  o.rtol = o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_names(*model);
  double err_F = 0, max_M = 0;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const double t = s.t;
    const Vector3d ac = -Omega * Omega * l * std::sin(theta) *
                        Vector3d(std::sin(Omega * t), -std::cos(Omega * t), 0);
    const Vector3d F = m * ac + m * g * Vector3d::UnitZ();
    err_F = std::max(err_F, (s.derived.segment<3>(fx) - Rj.transpose() * F).cwiseAbs().maxCoeff());
    max_M = std::max(max_M, s.derived.segment<3>(mx).cwiseAbs().maxCoeff());
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("spherical joint of the top: max |F - Newton| " << err_F << " N, max |M| " << max_M);
  BOOST_TEST(err_F < 1e-6);
  BOOST_TEST(max_M < 1e-12);
}

// Each joint between a generic ground marker (at (1, 2, 3), turned by 0.6 rad about (1, 2, 2))
// and a generic body marker (at (0.1, -0.2, 0.3), turned by -0.4 rad about (0, 1, 1)), in the
// assembled pose (frames coincident; for `distance` marker2 sits 0.5 along marker1's x): the
// rows vanish, have the rank the joint removes, and of the six unit twists of marker2 relative
// to marker1 (joint-frame components) exactly the allowed ones satisfy g q_d = 0.
BOOST_AUTO_TEST_CASE(each_spatial_joint_removes_exactly_its_relative_motions) {
  struct Case {
    std::string type;
    std::string allowed;  // of "vx vy vz wx wy wz"
    int rank;
  };
  const std::vector<Case> cases{
      {"fixed", "", 6},          {"revolute", "wz", 5},          {"prismatic", "vz", 5},
      {"cylindrical", "vz wz", 4}, {"spherical", "wx wy wz", 3},   {"universal", "wx wy", 4},
      {"planar", "vx vy wz", 3}, {"point_on_line", "vz wx wy wz", 2},
      {"point_on_plane", "vx vy wx wy wz", 1}, {"distance", "vy vz wx wy wz", 1}};
  const Vector3d p1(1, 2, 3), p2(0.1, -0.2, 0.3);
  const Vector3d ax1(1, 2, 2), ax2(0, 1, 1);
  const double an1 = 0.6, an2 = -0.4;
  const Matrix3d R1 = Eigen::AngleAxisd(an1, ax1.normalized()).toRotationMatrix();
  const Matrix3d R2 = Eigen::AngleAxisd(an2, ax2.normalized()).toRotationMatrix();
  const char* names[6] = {"vx", "vy", "vz", "wx", "wy", "wz"};
  for (const auto& c : cases) {
    std::ostringstream text;
    text << "[model]\nname = \"j\"\n"
         << "[model.body.ground.markers]\nm1 = { at = [1, 2, 3], axis = [1, 2, 2], angle = 0.6 }\n"
         << "[model.body.b]\nkind = \"spatial\"\nmass = 1.5\ninertia = [0.2, 0.3, 0.4]\n"
         << "markers.m2 = { at = [0.1, -0.2, 0.3], axis = [0, 1, 1], angle = -0.4 }\n"
         << "[model.joint.j]\ntype = \"" << c.type << "\"\nbody1 = \"ground\"\nmarker1 = \"m1\"\n"
         << "body2 = \"b\"\nmarker2 = \"m2\"\n"
         << (c.type == "distance" ? "length = 0.5\n" : "");
    const auto desc = load_model_text(text.str(), "joint_" + c.type + ".toml");
    const auto model = desc->instantiate({});
    // Assembled pose: A R2 = R1, marker2 at P1 (+ 0.5 u1 for distance).
    const Matrix3d A = R1 * R2.transpose();
    const Vector3d P2 = c.type == "distance" ? Vector3d(p1 + 0.5 * R1.col(0)) : p1;
    const Vector4d e = e_of_matrix(A);
    BOOST_REQUIRE((A_of(e) - A).norm() < 1e-14);
    Eigen::VectorXd q(7);
    q << P2 - A * p2, e;
    const std::vector<int> rows = all_rows(*model);
    const int s = static_cast<int>(rows.size());
    Eigen::MatrixXd g(s, 7);
    Eigen::VectorXd g0(s), gamma(s);
    Eigen::VectorXd qd0 = Eigen::VectorXd::Zero(7);
    model->constraint_rows(rows, 0.0, q, qd0, g, g0, gamma);
    double phi = 0;
    for (int i = 0; i < s; ++i)
      if (model->constraints()[rows[i]].kind == mech::ConstraintKind::holonomic)
        phi = std::max(phi, std::abs(model->position_residual(rows[i], 0.0, q)));
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(g);
    int rank = 0;
    for (int i = 0; i < svd.singularValues().size(); ++i)
      if (svd.singularValues()[i] > 1e-9 * svd.singularValues()[0]) ++rank;
    BOOST_TEST(phi < 1e-14, c.type << ": residual " << phi);
    BOOST_TEST(rank == c.rank + 1, c.type << ": rank " << rank << " (with the norm row)");
    for (int k = 0; k < 6; ++k) {
      Vector3d vrel = Vector3d::Zero(), wrel = Vector3d::Zero();
      (k < 3 ? vrel : wrel)[k % 3] = 1.0;
      const Vector3d w = R1 * wrel, vP = R1 * vrel;
      Eigen::VectorXd qd(7);
      qd << vP - w.cross(A * p2), 0.5 * E_of(e).transpose() * w;
      const double viol = (g * qd).cwiseAbs().maxCoeff();
      const bool allowed = c.allowed.find(names[k]) != std::string::npos;
      if (allowed) BOOST_TEST(viol < 1e-12, c.type << ": allowed " << names[k] << " violates by " << viol);
      else BOOST_TEST(viol > 1e-3, c.type << ": forbidden " << names[k] << " satisfies the rows (" << viol << ")");
    }
  }
}

// Bad inertia tensors: the error names the key and says what was expected.
namespace {

// A coin rolling on a deck that a drive moves along ground x with constant acceleration A (the
// deck: a spatial body on prismatic rows, the drive prescribing its travel A t^2/2); and the
// same coin on a fixed plane under the gravity the deck's frame feels, (-A, 0, -g).
const char* kCoinOnDeck = R"(
[model]
name = "coin_on_deck"
[model.parameters]
coin_m = 0.1
r = 0.05
g = 9.81
A = 1.5
X0 = 700.0
Y0 = -400.0
Z0 = 30.0
[model.body.ground.markers]
rail = { at = ["X0", "Y0", "Z0"], axis = [0, 1, 0], angle = "pi/2" }
[model.body.deck]
kind = "spatial"
mass = 5.0
inertia = [0.4, 0.5, 0.6]
markers.rail = { at = [0, 0, 0], axis = [0, 1, 0], angle = "pi/2" }
markers.plane = [0, 0, 0]
[model.joint.slide]
type = "prismatic"
marker1 = "rail"
body2 = "deck"
marker2 = "rail"
[model.joint.motor]
type = "drive"
joint = "slide"
motion = "A*t^2/2"
[model.body.coin]
kind = "spatial"
mass = "coin_m"
inertia = ["coin_m*r^2/4", "coin_m*r^2/4", "coin_m*r^2/2"]
[model.joint.roll]
type = "wheel"
body1 = "deck"
marker1 = "plane"
body2 = "coin"
radius = "r"
[model.force.gravity]
type = "gravity"
g = [0, 0, "-g"]
)";

const char* kCoinTiltedGravity = R"(
[model]
name = "coin_tilted_gravity"
[model.parameters]
coin_m = 0.1
r = 0.05
g = 9.81
A = 1.5
X0 = 700.0
Y0 = -400.0
Z0 = 30.0
[model.body.ground.markers]
plane = ["X0", "Y0", "Z0"]
[model.body.coin]
kind = "spatial"
mass = "coin_m"
inertia = ["coin_m*r^2/4", "coin_m*r^2/4", "coin_m*r^2/2"]
[model.joint.roll]
type = "wheel"
marker1 = "plane"
body2 = "coin"
radius = "r"
[model.force.gravity]
type = "gravity"
g = ["-A", 0, "-g"]
)";

}  // namespace

// The wheel joint on a moving body's plane (its rows subtract the deck's velocity at the
// contact): in the deck's frame, accelerating at A, the coin moves as on a fixed plane under
// the gravity (-A, 0, -g) (the d'Alembert force -m A), and the contact force, a real force, is
// the same. Both models start with the coin leaning and rolling (models/rolling_coin.toml's
// initial state), the deck at rest, 800 m from the origin; over 2 s (the deck travels 3 m)
// the coin's position relative to the deck, its Euler parameters and F_roll agree to 1e-7.
BOOST_AUTO_TEST_CASE(wheel_on_an_accelerating_deck_rolls_as_on_a_plane_under_tilted_gravity) {
  const double A = 1.5, t_end = 2.0, dt = 0.05;
  const Vector3d P0(700.0, -400.0, 30.0);
  // rolling_coin.toml's initial state, relative to the plane's marker.
  Eigen::VectorXd c(7), cd(7);
  c << 0.0, 0.014776010333066978, 0.047766824456280305, 0.5934980174097721, -0.8048354510896434, 0, 0;
  cd << 1.0032805345291167, 0, 0, 0, 0, 7.505907072219713, 6.72586112150093;
  c.head<3>() += P0;
  struct Trace {
    std::vector<Eigen::VectorXd> coin;  // x y z (relative to the plane's marker) e0..e3
    std::vector<Vector3d> F;
  };
  auto run = [&](const char* text, const char* name, bool deck) {
    const auto desc = load_model_text(text, name);
    const auto& names = desc->coordinates();
    Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
    const int ic = name_index(names, "coin_x");
    q.segment<7>(ic) = c;
    qd.segment<7>(ic) = cd;
    if (deck) {
      q.segment<3>(name_index(names, "deck_x")) = P0;
      q[name_index(names, "deck_e0")] = 1.0;
    }
    const auto model = desc->instantiate({}, q);
    const int iF = output_index(*desc, "F_roll_x");
    mech::SimulationOptions o;
    o.t_end = t_end;
    o.rtol = 1e-10;
    o.atol = 1e-12;
    o.kernel = Kernel::cpp;
    o.active_constraints = all_names(*model);
    Trace tr;
    int next = 0;
    const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
      while (next * dt <= v.t + 1e-12) {
        const mech::Sample s = v.sample(std::max(v.t_prev, next * dt));
        Eigen::VectorXd x = s.q.segment<7>(ic);
        x.head<3>() -= P0 + (deck ? Vector3d(0.5 * A * s.t * s.t, 0, 0) : Vector3d::Zero());
        tr.coin.push_back(x);
        tr.F.push_back(s.derived.segment<3>(iF));
        ++next;
      }
      return true;
    });
    BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
    return tr;
  };
  const Trace moving = run(kCoinOnDeck, "coin_on_deck.toml", true);
  const Trace fixed = run(kCoinTiltedGravity, "coin_tilted_gravity.toml", false);
  BOOST_REQUIRE(moving.coin.size() == fixed.coin.size());
  BOOST_REQUIRE(moving.coin.size() == 41u);
  double err_q = 0, err_F = 0, drift = 0, F_max = 0;
  for (std::size_t k = 0; k < moving.coin.size(); ++k) {
    err_q = std::max(err_q, (moving.coin[k] - fixed.coin[k]).cwiseAbs().maxCoeff());
    err_F = std::max(err_F, (moving.F[k] - fixed.F[k]).cwiseAbs().maxCoeff());
    F_max = std::max(F_max, fixed.F[k].cwiseAbs().maxCoeff());
    drift = std::max(drift, (fixed.coin[k].head<3>() - fixed.coin[0].head<3>()).norm());
  }
  BOOST_TEST_MESSAGE("coin on an accelerating deck vs tilted gravity: |q difference| " << err_q << ", |F_roll difference| "
                     << err_F << " N (of " << F_max << "); the coin moves " << drift << " m on the plane");
  BOOST_TEST(drift > 0.5);  // it rolls, and the tilted gravity shows
  BOOST_TEST(err_q < 1e-7);
  BOOST_TEST(err_F < 1e-7 * F_max);
}

namespace {

// models/wheel_in_bowl_bodies.toml's data, written again.
const double kBm = 2.0, kBr = 0.2, kBR = 1.0, kBg = 9.81;
const Vector3d kBS(300.0, -150.0, 40.0);

// A state of the wheel (upright, its axis along ground y) on the sphere in the plane y = Y0: at
// the angle th from the bottom (inside) or the top (outside), rolling at th_d, pivoting about
// the normal at wn. e_hat: from the sphere's centre to the contact; the centre at
// S + (R -/+ r) e_hat; the spin (R -/+ r) th_d / r about the axis for no slip.
State bowl_state(bool inside, double th, double thd, double wn) {
  const double s = std::sin(th), c = std::cos(th), L = inside ? kBR - kBr : kBR + kBr;
  const Vector3d eh = inside ? Vector3d(s, 0, -c) : Vector3d(s, 0, c);
  const Vector3d t = inside ? Vector3d(c, 0, s) : Vector3d(c, 0, -s);  // d(e_hat)/d(th)
  const Eigen::Quaterniond e(Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitX()));
  const Vector3d w = L * thd / kBr * Vector3d::UnitY() + wn * eh;
  const Eigen::Quaterniond ed = Eigen::Quaterniond(0, 0.5 * w[0], 0.5 * w[1], 0.5 * w[2]) * e;
  State st;
  st.q.resize(7);
  st.qd.resize(7);
  st.q << kBS + L * eh, e.w(), e.x(), e.y(), e.z();
  st.qd << L * thd * t, ed.w(), ed.x(), ed.y(), ed.z();
  return st;
}

// The reduced pendulum: 3/2 L th_dd = -/+ g sin(th), L = R -/+ r (inside / outside), by RK4.
struct Pendulum {
  bool inside;
  double L() const { return inside ? kBR - kBr : kBR + kBr; }
  double acc(double th) const { return (inside ? -1 : 1) * kBg * std::sin(th) / (1.5 * L()); }
  void step(double& th, double& thd, double h) const {
    pcsim::testing::rk4_step(th, thd, h, [this](double a) { return acc(a); });
  }
};

}  // namespace

// A wheel (a thin disk) upright in a vertical plane through the sphere's centre, rolling on
// the sphere (`wheel`, surface = "sphere"): inside the bowl it rocks as a pendulum of length
// L = R - r slowed by its spin, 3/2 L th_dd = -g sin(th) (T = 3/4 m L^2 th_d^2); outside, from
// near the top, it rolls off as 3/2 L th_dd = g sin(th), L = R + r. The oracle: that equation by
// RK4 (h = 1e-4 s); the contact force on the wheel is N along the normal (m g cos(th) + m L th_d^2
// inside, m g cos(th) - m L th_d^2 outside) and m L th_dd +/- m g sin(th) along the path.
// Inside from th = 1 rad at rest over 3 s (1.3 swings), outside from 0.1 rad at 0.3 rad/s over
// 0.8 s; position to 1e-7 m, forces to 1e-6 of m g (rtol 1e-10).
BOOST_AUTO_TEST_CASE(wheel_rolling_on_a_sphere_in_a_vertical_plane_follows_the_reduced_pendulum) {
  for (const bool inside : {true, false}) {
    BOOST_TEST_CONTEXT((inside ? "inside" : "outside")) {
      std::string text = model_text("wheel_in_bowl_bodies.toml");
      if (!inside) {
        const auto at = text.find("inside = true");
        BOOST_REQUIRE(at != std::string::npos);
        text.replace(at, 13, "inside = false");
      }
      const auto desc = load_model_text(text, "wheel_on_sphere.toml");
      const auto model = desc->instantiate({});
      const double th0 = inside ? 1.0 : 0.1, thd0 = inside ? 0.0 : 0.3, t_end = inside ? 3.0 : 0.8;
      const State s0 = bowl_state(inside, th0, thd0, 0.0);
      const Pendulum pend{inside};
      const double L = pend.L(), dt = 0.05, h = 1e-4;
      const int iF = output_index(*desc, "F_roll_x"), iN = output_index(*desc, "normal");
      double th = th0, thd = thd0, t_oracle = 0, err_x = 0, err_F = 0, err_N = 0, th_min = th0, th_max = th0;
      mech::SimulationOptions o;
      o.t_end = t_end;
      o.rtol = 1e-10;
      o.atol = 1e-12;
      o.kernel = Kernel::cpp;
      o.active_constraints = all_names(*model);
      int next = 0;
      const auto r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
        while (next * dt <= v.t + 1e-12) {
          const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
          while (t_oracle < smp.t - 1e-12) {
            pend.step(th, thd, h);
            t_oracle += h;
          }
          th_min = std::min(th_min, th);
          th_max = std::max(th_max, th);
          const double sn = std::sin(th), cs = std::cos(th);
          const Vector3d eh = inside ? Vector3d(sn, 0, -cs) : Vector3d(sn, 0, cs);
          const Vector3d tt = inside ? Vector3d(cs, 0, sn) : Vector3d(cs, 0, -sn);
          err_x = std::max(err_x, (smp.q.head<3>() - (kBS + L * eh)).cwiseAbs().maxCoeff());
          const double N = inside ? kBm * kBg * cs + kBm * L * thd * thd : kBm * kBg * cs - kBm * L * thd * thd;
          const double f = kBm * L * pend.acc(th) + (inside ? 1 : -1) * kBm * kBg * sn;
          const Vector3d F = (inside ? -N : N) * eh + f * tt;
          err_F = std::max(err_F, (smp.derived.segment<3>(iF) - F).cwiseAbs().maxCoeff());
          err_N = std::max(err_N, std::abs(smp.derived[iN] - N));
          ++next;
        }
        return true;
      });
      BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
      BOOST_TEST_MESSAGE("wheel " << (inside ? "inside" : "outside") << " a sphere, th in [" << th_min << ", " << th_max
                         << "]: |centre - pendulum| " << err_x << " m, |F_roll - Newton| " << err_F
                         << " N, |lambda_n - N| " << err_N << " N");
      BOOST_TEST((inside ? th_min < -0.9 : th_max > 0.5));  // it swings (rolls off)
      BOOST_TEST(err_x < 1e-7);
      BOOST_TEST(err_F < 1e-6 * kBm * kBg);
      BOOST_TEST(err_N < 1e-6 * kBm * kBg);
    }
  }
}

// A wheel leaving the vertical plane in the bowl (started 0.8 rad up its side, rolling at
// 2 rad/s and pivoting about the normal at 1 rad/s; over 1.5 s it leans and runs out of the
// plane): at every 0.05 s, the rim's farthest point from the sphere's centre, found by search
// over the rim (4,000 points, golden section, then Newton on the stationarity), is R from it to
// 5e-9 m (measured 5.4e-10); the wheel's material point there does not move (5e-8 m/s, measured
// 6.8e-9; the engine's own velocity residual on the rows reaches 1.2e-8); and the energy stays at
// its initial value to 5e-8 of the kinetic energy (measured 5.8e-9 at rtol 1e-10: ideal rows do
// no work). None of this uses the joint's contact-point formula; a wrong contact point (the
// nearest rim point instead of the farthest, a rho off by the tilt) misses by millimetres.
BOOST_AUTO_TEST_CASE(wheel_in_a_bowl_touches_at_the_searched_contact_point_without_slip) {
  const auto desc = load_model_file(model_path("wheel_in_bowl_bodies.toml"));
  const auto model = desc->instantiate({});
  const State s0 = bowl_state(true, 0.8, 2.0, 1.0);
  const int iE = output_index(*desc, "energy");
  mech::SimulationOptions o;
  o.t_end = 1.5;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_names(*model);
  double E0 = std::nan(""), T0 = 0, err_E = 0, err_d = 0, err_v = 0, y_off = 0, res_v = 0;
  const double dt = 0.05;
  int next = 0;
  const auto r = mech::simulate(*model, s0.q, s0.qd, o, [&](const mech::StepView& v) {
    while (next * dt <= v.t + 1e-12) {
      const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
      const Vector3d C = smp.q.head<3>(), vC = smp.qd.head<3>();
      const Vector4d e = smp.q.segment<4>(3), ed = smp.qd.segment<4>(3);
      const Matrix3d A = A_of(e);
      const Vector3d w = 2 * E_of(e) * ed;  // ground axes
      if (next == 0) {
        E0 = smp.derived[iE];
        const Vector3d wb = A.transpose() * w;
        T0 = 0.5 * kBm * vC.squaredNorm() +
             0.5 * (kBm * kBr * kBr / 4 * (wb[0] * wb[0] + wb[1] * wb[1]) + kBm * kBr * kBr / 2 * wb[2] * wb[2]);
      }
      err_E = std::max(err_E, std::abs(smp.derived[iE] - E0));
      auto dist = [&](double phi) {
        return (C + kBr * (std::cos(phi) * A.col(0) + std::sin(phi) * A.col(1)) - kBS).norm();
      };
      int best = 0;
      const int n = 4000;
      for (int k = 1; k < n; ++k)
        if (dist(2 * M_PI * k / n) > dist(2 * M_PI * best / n)) best = k;
      double lo = 2 * M_PI * (best - 1) / n, hi = 2 * M_PI * (best + 1) / n;
      const double gr = (std::sqrt(5.0) - 1) / 2;
      for (int it = 0; it < 60; ++it) {
        const double a = hi - gr * (hi - lo), b = lo + gr * (hi - lo);
        if (dist(a) > dist(b)) hi = b;
        else lo = a;
      }
      // The maximum is flat (the distance resolves phi to ~1e-8 only): Newton on its
      // stationarity, (C + rho - S) . rho'(phi) = 0, for phi to rounding.
      double phi = 0.5 * (lo + hi);
      for (int it = 0; it < 4; ++it) {
        const Vector3d rp = kBr * (std::cos(phi) * A.col(0) + std::sin(phi) * A.col(1));
        const Vector3d rd = kBr * (-std::sin(phi) * A.col(0) + std::cos(phi) * A.col(1));
        const Vector3d D = C + rp - kBS;
        phi -= D.dot(rd) / (rd.squaredNorm() - D.dot(rp));
      }
      const Vector3d rho = kBr * (std::cos(phi) * A.col(0) + std::sin(phi) * A.col(1));
      err_d = std::max(err_d, std::abs((C + rho - kBS).norm() - kBR));
      err_v = std::max(err_v, (vC + w.cross(rho)).norm());
      y_off = std::max(y_off, std::abs(C[1] - kBS[1]));
      res_v = std::max(res_v, smp.residual_vel);
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("wheel in a bowl, out of the plane by " << y_off << " m: |max rim distance - R| " << err_d
                     << " m, contact point speed " << err_v << " m/s (the engine's velocity residual " << res_v
                     << "), |E - E0| " << err_E << " J (T0 " << T0 << " J)");
  BOOST_TEST(y_off > 0.05);
  BOOST_TEST(err_d < 5e-9);
  BOOST_TEST(err_v < 5e-8);
  BOOST_TEST(err_E < 5e-8 * T0);
}

namespace {

// A bead on a rod that a drive spins at a constant rate w about the vertical (a revolute tree
// joint at a hub far from the origin); the bead slides freely along the rod: by a prismatic
// tree joint (coordinate s), or written as rows (the bead absolute, in Euler parameters).
std::string bead_on_rod(bool tree) {
  std::string t = R"(
[model]
name = "bead_on_rod"
[model.parameters]
m = 0.3
w = 2.0
g = 9.81
[model.body.ground.markers]
hub = [100, 200, 5]
[model.body.rod]
kind = "spatial"
mass = 1.0
inertia = [0.01, 0.2, 0.2]
markers.guide = { at = [0, 0, 0], axis = [0, 1, 0], angle = "pi/2" }
[model.joint.spin]
type = "revolute"
marker1 = "hub"
body2 = "rod"
coordinates = ["phi"]
[model.joint.motor]
type = "drive"
joint = "spin"
motion = "w*t"
[model.body.bead]
kind = "spatial"
mass = "m"
inertia = [1e-4, 1e-4, 1e-4]
markers.m = { at = [0, 0, 0], axis = [0, 1, 0], angle = "pi/2" }
[model.joint.slide]
type = "prismatic"
body1 = "rod"
marker1 = "guide"
body2 = "bead"
marker2 = "m"
[model.force.gravity]
type = "gravity"
g = [0, 0, "-g"]
)";
  if (tree) t.replace(t.find("marker2 = \"m\"\n"), 14, "marker2 = \"m\"\ncoordinates = [\"s\"]\n");
  return t;
}

}  // namespace

// A prismatic joint between spatial bodies, as a tree joint (the bead placed by its travel s)
// and as rows: on a rod spun at w, the bead runs out as s = s0 cosh(w t) (s_dd = w^2 s); the
// drive's torque is dH/dt = 2 m w s s_d; the rows' reaction on the bead, in the guide's frame
// (x down, y along the rod's turning, z along the rod), is (-m g, 2 m w s_d, 0) (Coriolis and
// weight) with no moment. 1 s (s grows 3.8 times), to 1e-8 relative.
BOOST_AUTO_TEST_CASE(prismatic_joint_between_spatial_bodies_as_tree_joint_and_as_rows_follows_the_closed_form) {
  const double m = 0.3, w = 2.0, g = 9.81, s0 = 0.1;
  const Vector3d hub(100, 200, 5);
  for (const bool tree : {true, false}) {
    BOOST_TEST_CONTEXT((tree ? "tree joint" : "rows")) {
      const auto desc = load_model_text(bead_on_rod(tree), "bead_on_rod.toml");
      const auto& names = desc->coordinates();
      BOOST_REQUIRE(names.size() == (tree ? 2u : 8u));
      Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
      qd[name_index(names, "phi")] = w;
      if (tree) {
        q[name_index(names, "s")] = s0;
      } else {
        const int ix = name_index(names, "bead_x"), ie = name_index(names, "bead_e0");
        q.segment<3>(ix) = hub + Vector3d(s0, 0, 0);
        q[ie] = 1.0;
        qd.segment<3>(ix) = Vector3d(0, w * s0, 0);
        qd[ie + 3] = 0.5 * w;  // e_d = 1/2 (0, w z) at e = 1
      }
      const auto model = desc->instantiate({});
      const int iM = output_index(*desc, "M_motor_z");
      const int iF = tree ? -1 : output_index(*desc, "F_slide_x");
      const int iMs = tree ? -1 : output_index(*desc, "M_slide_x");
      mech::SimulationOptions o;
      o.t_end = 1.0;
      o.rtol = 1e-11;
      o.atol = 1e-13;
      o.kernel = Kernel::cpp;
      o.active_constraints = all_names(*model);
      double err_s = 0, err_M = 0, err_F = 0, max_Ms = 0, s_end = 0;
      int next = 0;
      const double dt = 0.05;
      const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
        while (next * dt <= v.t + 1e-12) {
          const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
          const double t = smp.t, s = s0 * std::cosh(w * t), sd = s0 * w * std::sinh(w * t);
          const Vector3d P = tree ? Vector3d::Zero() : Vector3d(smp.q.segment<3>(name_index(names, "bead_x")));
          const double s_run = tree ? smp.q[name_index(names, "s")] : (P - hub).norm();
          err_s = std::max(err_s, std::abs(s_run - s) / s);
          s_end = s_run;
          // relative to the torque at the end, 2 m w s0^2 w cosh(w) sinh(w)
          const double M_end = 2 * m * w * s0 * s0 * w * std::cosh(w) * std::sinh(w);
          err_M = std::max(err_M, std::abs(smp.derived[iM] - 2 * m * w * s * sd) / M_end);
          if (!tree) {
            const Vector3d F(-m * g, 2 * m * w * sd, 0);
            err_F = std::max(err_F, (smp.derived.segment<3>(iF) - F).cwiseAbs().maxCoeff() / (m * g));
            max_Ms = std::max(max_Ms, smp.derived.segment<3>(iMs).cwiseAbs().maxCoeff());
          }
          ++next;
        }
        return true;
      });
      BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
      BOOST_TEST_MESSAGE("bead on a spinning rod (" << (tree ? "prismatic tree joint" : "prismatic rows") << "): s "
                         << s0 << " -> " << s_end << " m, |s - s0 cosh(w t)|/s " << err_s << ", drive torque rel "
                         << err_M << ", slide force rel " << err_F << (tree ? " (a tree joint has no rows)" : ""));
      BOOST_TEST(s_end > 3.5 * s0);
      BOOST_TEST(err_s < 1e-8);
      BOOST_TEST(err_M < 1e-7);
      BOOST_TEST(err_F < 1e-8);
      BOOST_TEST(max_Ms < 1e-8);
    }
  }
}

namespace {

// The bead's rod again, now carrying a sleeve on a cylindrical joint: it slides along the rod
// and turns about it. The sleeve's inertia is not a sphere's and its centre is off the axis, so
// its turning and the rod's spin are coupled. By a cylindrical tree joint (coordinates psi,
// s) or as rows (the sleeve in Euler parameters). Outputs: the sleeve's origin and rotation.
std::string sleeve_on_rod(bool tree) {
  std::string t = R"(
[model]
name = "sleeve_on_rod"
[model.parameters]
m = 0.3
w = 2.0
g = 9.81
[model.body.ground.markers]
hub = [100, 200, 5]
[model.body.rod]
kind = "spatial"
mass = 1.0
inertia = [0.01, 0.2, 0.2]
markers.guide = { at = [0, 0, 0], axis = [0, 1, 0], angle = "pi/2" }
[model.joint.spin]
type = "revolute"
marker1 = "hub"
body2 = "rod"
coordinates = ["phi"]
[model.joint.motor]
type = "drive"
joint = "spin"
motion = "w*t"
[model.body.sleeve]
kind = "spatial"
mass = "m"
inertia = [[4e-3, 0, 0], [0, 5e-3, 1e-3], [0, 1e-3, 7e-3]]
markers.m = { at = [0.02, -0.03, 0.01], axis = [0, 1, 0], angle = "pi/2" }
[model.joint.slide]
type = "cylindrical"
body1 = "rod"
marker1 = "guide"
body2 = "sleeve"
marker2 = "m"
[model.force.gravity]
type = "gravity"
g = [0, 0, "-g"]
[model.outputs]
px = "sleeve_x"
py = "sleeve_y"
pz = "sleeve_z"
a11 = "sleeve_a11"
a12 = "sleeve_a12"
a13 = "sleeve_a13"
a21 = "sleeve_a21"
a22 = "sleeve_a22"
a23 = "sleeve_a23"
a31 = "sleeve_a31"
a32 = "sleeve_a32"
a33 = "sleeve_a33"
)";
  if (tree) t.replace(t.find("marker2 = \"m\"\n"), 14, "marker2 = \"m\"\ncoordinates = [\"psi\", \"s\"]\n");
  return t;
}

}  // namespace

// A cylindrical joint between spatial bodies, as a tree joint (the sleeve placed by its angle
// psi and travel s) and as rows (the sleeve absolute, in Euler parameters: an independent
// formulation of the same machine). The sleeve starts at s0 on the rod spun at w, turning about
// it at 3 rad/s; its centre is off the axis and its inertia has a product term, so it wobbles
// and its travel is coupled to its turning. Oracle: the two formulations agree on the sleeve's
// origin and rotation matrix over 1 s to 1e-8 (m, and of 1; measured 3e-11 m and 3.4e-10, the
// two runs' global errors at rtol 1e-11).
BOOST_AUTO_TEST_CASE(cylindrical_joint_between_spatial_bodies_as_tree_joint_and_as_rows_agree) {
  const double w = 2.0, s0 = 0.1, psid0 = 3.0;
  const Vector3d hub(100, 200, 5);
  std::map<bool, std::vector<Eigen::VectorXd>> seen;  // the outputs px..a33 every 0.05 s
  for (const bool tree : {true, false}) {
    BOOST_TEST_CONTEXT((tree ? "tree joint" : "rows")) {
      const auto desc = load_model_text(sleeve_on_rod(tree), "sleeve_on_rod.toml");
      const auto& names = desc->coordinates();
      BOOST_REQUIRE(names.size() == (tree ? 3u : 8u));
      Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
      qd[name_index(names, "phi")] = w;
      // marker m at c = (0.02, -0.03, 0.01) in the sleeve's frame, its z along the sleeve's x:
      // at psi = 0 the sleeve's axes are the rod's (marker frames alike), and its origin is
      // the point s0 along the rod (ground x at t = 0) less c.
      const Vector3d c(0.02, -0.03, 0.01);
      if (tree) {
        q[name_index(names, "s")] = s0;
        qd[name_index(names, "psi")] = psid0;
      } else {
        const int ix = name_index(names, "sleeve_x"), ie = name_index(names, "sleeve_e0");
        q.segment<3>(ix) = hub + Vector3d(s0, 0, 0) - c;
        q[ie] = 1.0;
        // ω = (psid0, 0, w) in ground; the origin's velocity ω × (origin − hub) (the sleeve's
        // point on the axis moves at w ẑ × s0 x̂; the rest turns with ω)
        const Vector3d omega(psid0, 0, w);
        qd.segment<3>(ix) = Vector3d(0, w * s0, 0) + omega.cross(-c);
        qd.segment<3>(ie + 1) = 0.5 * omega;  // e_d = 1/2 (0, ω) at e = 1
      }
      const auto model = desc->instantiate({});
      const int i0 = output_index(*desc, "px");
      mech::SimulationOptions o;
      o.t_end = 1.0;
      o.rtol = 1e-11;
      o.atol = 1e-13;
      o.kernel = Kernel::cpp;
      o.active_constraints = all_names(*model);
      int next = 0;
      const double dt = 0.05;
      auto& out = seen[tree];
      const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
        while (next * dt <= v.t + 1e-12) {
          const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
          out.push_back(smp.derived.segment(i0, 12));
          ++next;
        }
        return true;
      });
      BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
      BOOST_TEST(out.size() == 21u);
      if (tree) {
        BOOST_TEST(r.q_end[name_index(names, "s")] > 1.5 * s0);  // it runs out along the rod
        // the sleeve turned about the rod, not at a constant rate (the coupling)
        const double psi = r.q_end[name_index(names, "psi")];
        BOOST_TEST(std::abs(psi - psid0) > 1e-3);
        BOOST_TEST_MESSAGE("sleeve on a cylindrical tree joint: s " << s0 << " -> "
                           << r.q_end[name_index(names, "s")] << " m, psi 0 -> " << psi << " rad");
      }
    }
  }
  double err_p = 0, err_a = 0;
  for (std::size_t k = 0; k < seen[true].size() && k < seen[false].size(); ++k) {
    err_p = std::max(err_p, (seen[true][k].head(3) - seen[false][k].head(3)).cwiseAbs().maxCoeff());
    err_a = std::max(err_a, (seen[true][k].tail(9) - seen[false][k].tail(9)).cwiseAbs().maxCoeff());
  }
  BOOST_TEST_MESSAGE("cylindrical joint, tree against rows over 1 s: origin " << err_p << " m, rotation " << err_a);
  BOOST_TEST(err_p < 1e-8);
  BOOST_TEST(err_a < 1e-8);
}

// Drives on a cylindrical tree joint's two coordinates: a sleeve on a tilted shaft (axis in
// ground x-z at 30 degrees from vertical, far from the origin), its travel prescribed at 1 m/s and
// its angle at 2 rad/s. The drives' reactions are the force along the axis that holds the
// weight's component m g cos 30° (F_z, the joint's frame) and no torque about the axis (an
// axisymmetric sleeve turning steadily): closed form, to 1e-10.
BOOST_AUTO_TEST_CASE(drives_on_a_cylindrical_tree_joint_give_the_axial_force_and_torque) {
  const double m = 2.5, g = 9.81, beta = std::acos(-1.0) / 6;
  const std::string text = R"([model]
name = "sleeve_drives"
[model.body.ground.markers]
shaft = { at = [300, -40, 12], axis = [0, 1, 0], angle = "pi/6" }
[model.body.sleeve]
kind = "spatial"
mass = 2.5
inertia = [0.02, 0.02, 0.01]
[model.joint.c]
type = "cylindrical"
marker1 = "shaft"
body2 = "sleeve"
coordinates = ["psi", "z"]
[model.joint.lift]
type = "drive"
joint = "c"
coordinate = "z"
motion = "t"
[model.joint.turn]
type = "drive"
joint = "c"
coordinate = "psi"
motion = "2*t"
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
)";
  const auto desc = load_model_text(text, "sleeve_drives.toml");
  const auto model = desc->instantiate({});
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2), qd = q;
  const auto& names = desc->coordinates();
  qd[name_index(names, "z")] = 1.0;
  qd[name_index(names, "psi")] = 2.0;
  mech::SimulationOptions o;
  o.t_end = 0.5;
  o.rtol = o.atol = 1e-12;
  o.active_constraints = all_names(*model);
  const int iF = output_index(*desc, "F_lift_z"), iM = output_index(*desc, "M_turn_z");
  double err_F = 0, err_M = 0;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    err_F = std::max(err_F, std::abs(s.derived[iF] - m * g * std::cos(beta)));
    err_M = std::max(err_M, std::abs(s.derived[iM]));
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "z")] - 0.5) < 1e-10);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "psi")] - 1.0) < 1e-10);
  BOOST_TEST(err_F < 1e-10 * m * g);
  BOOST_TEST(err_M < 1e-10);
}

// Spring-dampers on a cylindrical tree joint's coordinates: a sleeve on a vertical shaft with a
// spring along it (k, rest 0) and a rotational damper about it (c). Closed form: released at
// rest at z0, z = −m g/k + (z0 + m g/k) cos(√(k/m) t); turning at ψ̇0, ψ̇ = ψ̇0 e^(−c t/J), J the
// sleeve's moment about the shaft. Over 2 s, to 1e-8.
BOOST_AUTO_TEST_CASE(spring_dampers_act_on_a_cylindrical_tree_joints_travel_and_angle) {
  const double m = 2.0, g = 9.81, k = 800.0, c = 0.03, J = 0.01, z0 = 0.05, wd0 = 4.0;
  const std::string text = R"([model]
name = "sleeve_springs"
[model.body.ground.markers]
shaft = [-50, 70, 3]
[model.body.sleeve]
kind = "spatial"
mass = 2.0
inertia = [0.02, 0.02, 0.01]
[model.joint.c]
type = "cylindrical"
marker1 = "shaft"
body2 = "sleeve"
coordinates = ["psi", "z"]
[model.force.spring]
type = "joint_spring_damper"
joint = "c"
coordinate = "z"
stiffness = 800.0
rest = 0.0
[model.force.damper]
type = "joint_spring_damper"
joint = "c"
coordinate = "psi"
damping = 0.03
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
)";
  const auto desc = load_model_text(text, "sleeve_springs.toml");
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  const int iz = name_index(names, "z"), ip = name_index(names, "psi");
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2), qd = q;
  q[iz] = z0;
  qd[ip] = wd0;
  mech::SimulationOptions o;
  o.t_end = 2.0;
  o.rtol = o.atol = 1e-12;
  double err_z = 0, err_w = 0;
  const double om = std::sqrt(k / m), zs = -m * g / k;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    err_z = std::max(err_z, std::abs(s.q[iz] - (zs + (z0 - zs) * std::cos(om * v.t))));
    err_w = std::max(err_w, std::abs(s.qd[ip] - wd0 * std::exp(-c * v.t / J)));
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("sleeve on springs: |z - closed form| " << err_z << " m, |psi_d - closed form| " << err_w << " rad/s");
  BOOST_TEST(err_z < 1e-8);
  BOOST_TEST(err_w < 1e-8);
  BOOST_TEST(r.qd_end[ip] < 0.01 * wd0);  // the damper took 6 time constants
}

namespace {

// A bob hanging by a universal joint (Hooke's joint) from a shaft a drive spins about the
// vertical, far from the origin. The bob's inertia has a product term and the joint is 0.3 m
// above its origin. By a universal tree joint (the cross's angles al, be) or as rows (the bob in
// Euler parameters). Outputs: the bob's origin and rotation.
std::string bob_on_cross(bool tree) {
  std::string t = R"(
[model]
name = "bob_on_cross"
[model.parameters]
w = 3.0
[model.body.ground.markers]
hub = [100, 200, 5]
[model.body.shaft]
kind = "spatial"
mass = 1.0
inertia = [0.01, 0.01, 0.02]
markers.fork = [0, 0, -0.1]
[model.joint.spin]
type = "revolute"
marker1 = "hub"
body2 = "shaft"
coordinates = ["phi"]
[model.joint.motor]
type = "drive"
joint = "spin"
motion = "w*t"
[model.body.bob]
kind = "spatial"
mass = 0.5
inertia = [[4e-3, 0, 0], [0, 5e-3, 1e-3], [0, 1e-3, 7e-3]]
markers.m = [0, 0, 0.3]
[model.joint.cross]
type = "universal"
body1 = "shaft"
marker1 = "fork"
body2 = "bob"
marker2 = "m"
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
[model.outputs]
px = "bob_x"
py = "bob_y"
pz = "bob_z"
a11 = "bob_a11"
a12 = "bob_a12"
a13 = "bob_a13"
a21 = "bob_a21"
a22 = "bob_a22"
a23 = "bob_a23"
a31 = "bob_a31"
a32 = "bob_a32"
a33 = "bob_a33"
)";
  if (tree) t.replace(t.find("marker2 = \"m\"\n"), 14, "marker2 = \"m\"\ncoordinates = [\"al\", \"be\"]\n");
  return t;
}

}  // namespace

// A universal joint between spatial bodies, as a tree joint (the bob placed by the cross's two
// angles) and as rows (the bob in Euler parameters, the cross's row u1·v2 = 0): an independent
// formulation of the same machine. Released at the cross's zero angles turning at (1, 0.5)
// rad/s relative to the shaft spun at 3 rad/s, the bob swings and wobbles. Oracle: the two
// agree on its origin and rotation matrix over 1 s to 1e-8 (rtol 1e-11).
BOOST_AUTO_TEST_CASE(universal_joint_between_spatial_bodies_as_tree_joint_and_as_rows_agree) {
  const double w = 3.0, ad0 = 1.0, bd0 = 0.5;
  const Vector3d hub(100, 200, 5);
  std::map<bool, std::vector<Eigen::VectorXd>> seen;
  for (const bool tree : {true, false}) {
    BOOST_TEST_CONTEXT((tree ? "tree joint" : "rows")) {
      const auto desc = load_model_text(bob_on_cross(tree), "bob_on_cross.toml");
      const auto& names = desc->coordinates();
      BOOST_REQUIRE(names.size() == (tree ? 3u : 8u));
      Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
      qd[name_index(names, "phi")] = w;
      if (tree) {
        qd[name_index(names, "al")] = ad0;
        qd[name_index(names, "be")] = bd0;
      } else {
        // At the cross's zero angles the bob's axes are the shaft's (ground's at phi = 0); its
        // origin 0.3 m below the joint, which is 0.1 m below the hub on the axis (at rest).
        const int ix = name_index(names, "bob_x"), ie = name_index(names, "bob_e0");
        q.segment<3>(ix) = hub + Vector3d(0, 0, -0.4);
        q[ie] = 1.0;
        const Vector3d omega(ad0, bd0, w);  // α̇ x1 + β̇ y2 + the shaft's w z
        qd.segment<3>(ix) = omega.cross(Vector3d(0, 0, -0.3));
        qd.segment<3>(ie + 1) = 0.5 * omega;
      }
      const auto model = desc->instantiate({});
      const int i0 = output_index(*desc, "px");
      mech::SimulationOptions o;
      o.t_end = 1.0;
      o.rtol = 1e-11;
      o.atol = 1e-13;
      o.kernel = Kernel::cpp;
      o.active_constraints = all_names(*model);
      int next = 0;
      const double dt = 0.05;
      auto& out = seen[tree];
      const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
        while (next * dt <= v.t + 1e-12) {
          const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
          out.push_back(smp.derived.segment(i0, 12));
          ++next;
        }
        return true;
      });
      BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
      BOOST_TEST(out.size() == 21u);
      if (tree)
        BOOST_TEST_MESSAGE("bob on a universal tree joint: al " << r.q_end[name_index(names, "al")]
                           << " rad, be " << r.q_end[name_index(names, "be")] << " rad at 1 s");
    }
  }
  double err_p = 0, err_a = 0, swing = 0;
  for (std::size_t k = 0; k < seen[true].size() && k < seen[false].size(); ++k) {
    err_p = std::max(err_p, (seen[true][k].head(3) - seen[false][k].head(3)).cwiseAbs().maxCoeff());
    err_a = std::max(err_a, (seen[true][k].tail(9) - seen[false][k].tail(9)).cwiseAbs().maxCoeff());
    swing = std::max(swing, (seen[true][k].head(2) - hub.head(2)).norm());
  }
  BOOST_TEST_MESSAGE("universal joint, tree against rows over 1 s: origin " << err_p << " m, rotation "
                     << err_a << "; the bob swung out to " << swing << " m from the axis");
  BOOST_TEST(swing > 0.05);
  BOOST_TEST(err_p < 1e-8);
  BOOST_TEST(err_a < 1e-8);
}

// A drive on a universal tree joint's first angle: a body on a cross at its centre of mass,
// turned about the first arm (marker1's x) at a constant angular acceleration a, α = a t²/2,
// the second angle free (it stays 0: the body's principal axes are the arms). Closed form: the
// driving torque M_x = J_x a (the body's moment about the arm), M_y, M_z = 0; β = 0, to 1e-10.
BOOST_AUTO_TEST_CASE(a_drive_on_a_universal_tree_joints_first_angle_gives_the_torque_about_its_arm) {
  const double Jx = 0.04, a = 3.0;
  const std::string text = R"([model]
name = "cross_drive"
[model.body.ground.markers]
pivot = [-20, 35, 60]
[model.body.body]
kind = "spatial"
mass = 1.5
inertia = [0.04, 0.06, 0.09]
[model.joint.cross]
type = "universal"
marker1 = "pivot"
body2 = "body"
coordinates = ["al", "be"]
[model.joint.turn]
type = "drive"
joint = "cross"
coordinate = "al"
motion = "1.5*t^2"
)";
  const auto desc = load_model_text(text, "cross_drive.toml");
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2), qd = q;
  mech::SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = o.atol = 1e-12;
  o.active_constraints = all_names(*model);
  const int iM = output_index(*desc, "M_turn_x");
  double err_M = 0, other = 0;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    err_M = std::max(err_M, std::abs(s.derived[iM] - Jx * a));
    other = std::max({other, std::abs(s.derived[iM + 1]), std::abs(s.derived[iM + 2])});
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST(output_index(*desc, "M_turn_y") == iM + 1);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "al")] - 0.5 * a) < 1e-10);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "be")]) < 1e-10);
  BOOST_TEST(err_M < 1e-10);
  BOOST_TEST(other < 1e-10);
}

namespace {

// A bob on a ball joint under a shaft a drive spins about the vertical, far from the origin. Both
// markers are turned about skew axes (marker2's frame = marker1's · A(p) then differs from the
// bodies' frames) and marker2 is off the bob's axes; the bob's inertia has a product term. By a
// spherical tree joint (the relative Euler parameters p0..p3) or as rows (the bob in Euler
// parameters, the rows x, y, z). Outputs: the bob's origin and rotation.
std::string bob_on_ball(bool tree) {
  std::string t = R"(
[model]
name = "bob_on_ball"
[model.parameters]
w = 3.0
[model.body.ground.markers]
hub = [100, 200, 5]
[model.body.shaft]
kind = "spatial"
mass = 1.0
inertia = [0.01, 0.01, 0.02]
markers.fork = { at = [0, 0, -0.1], axis = [1, 1, 0], angle = 0.4 }
[model.joint.spin]
type = "revolute"
marker1 = "hub"
body2 = "shaft"
coordinates = ["phi"]
[model.joint.motor]
type = "drive"
joint = "spin"
motion = "w*t"
[model.body.bob]
kind = "spatial"
mass = 0.5
inertia = [[4e-3, 0, 0], [0, 5e-3, 1e-3], [0, 1e-3, 7e-3]]
markers.m = { at = [0.05, -0.02, 0.3], axis = [0, 1, 2], angle = -0.7 }
[model.joint.ball]
type = "spherical"
body1 = "shaft"
marker1 = "fork"
body2 = "bob"
marker2 = "m"
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
[model.outputs]
px = "bob_x"
py = "bob_y"
pz = "bob_z"
a11 = "bob_a11"
a12 = "bob_a12"
a13 = "bob_a13"
a21 = "bob_a21"
a22 = "bob_a22"
a23 = "bob_a23"
a31 = "bob_a31"
a32 = "bob_a32"
a33 = "bob_a33"
)";
  if (tree) t.replace(t.find("marker2 = \"m\"\n"), 14, "marker2 = \"m\"\ncoordinates = [\"p0\", \"p1\", \"p2\", \"p3\"]\n");
  return t;
}

}  // namespace

// A spherical joint between spatial bodies, as a tree joint (the bob placed by the Euler
// parameters of marker2's frame relative to marker1's, with their norm row) and as rows (the bob
// in its own Euler parameters, the rows x, y, z): an independent formulation of the same machine.
// Released at p = (1, 0, 0, 0) turning at (2, -1, 3) rad/s relative to the shaft (marker2's
// axes), the shaft spun at 3 rad/s, the bob tumbles through more than a half turn relative to the
// shaft (p0 changes sign: an orientation where some set of three angles is singular is passed).
// Oracle: the two agree on its origin and rotation matrix over 2 s to 1e-8 (rtol 1e-11); the
// norm row holds to 1e-10.
BOOST_AUTO_TEST_CASE(spherical_joint_between_spatial_bodies_as_tree_joint_and_as_rows_agree) {
  const double w = 3.0;
  const Vector3d hub(100, 200, 5), wrel(2, -1, 3), m2p(0.05, -0.02, 0.3);
  const Matrix3d R1 = Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Matrix3d R2 = Eigen::AngleAxisd(-0.7, Vector3d(0, 1, 2).normalized()).toRotationMatrix();
  std::map<bool, std::vector<Eigen::VectorXd>> seen;
  double p0_min = 1, norm_err = 0;
  for (const bool tree : {true, false}) {
    BOOST_TEST_CONTEXT((tree ? "tree joint" : "rows")) {
      const auto desc = load_model_text(bob_on_ball(tree), "bob_on_ball.toml");
      const auto& names = desc->coordinates();
      BOOST_REQUIRE(names.size() == (tree ? 5u : 8u));
      Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
      qd[name_index(names, "phi")] = w;
      if (tree) {
        // ṗ = ½ Gᵀ(p) ω' at p = (1, 0, 0, 0): (0, ω'/2), ω' in marker2's axes.
        q[name_index(names, "p0")] = 1.0;
        for (int i = 0; i < 3; ++i) qd[name_index(names, "p" + std::to_string(i + 1))] = 0.5 * wrel[i];
      } else {
        // At p = 1 marker2's frame is marker1's: A R2 = R1 (the shaft's frame is ground's at
        // phi = 0), the joint's centre J = hub − 0.1 ẑ, the bob's origin J − A m2.
        const Matrix3d A = R1 * R2.transpose();
        const Eigen::Quaterniond e(A);
        const Vector3d J = hub + Vector3d(0, 0, -0.1), r = J - A * m2p;
        const Vector3d omega = Vector3d(0, 0, w) + R1 * wrel;  // ground axes
        const int ix = name_index(names, "bob_x"), ie = name_index(names, "bob_e0");
        q.segment<3>(ix) = r;
        q.segment<4>(ie) << e.w(), e.x(), e.y(), e.z();
        qd.segment<3>(ix) = omega.cross(r - J);  // J is on the spin axis: at rest
        Eigen::Matrix<double, 3, 4> E;
        E << -e.x(), e.w(), -e.z(), e.y(),  //
            -e.y(), e.z(), e.w(), -e.x(),   //
            -e.z(), -e.y(), e.x(), e.w();
        qd.segment<4>(ie) = 0.5 * E.transpose() * omega;
      }
      const auto model = desc->instantiate({});
      const int i0 = output_index(*desc, "px");
      mech::SimulationOptions o;
      o.t_end = 2.0;
      o.rtol = 1e-11;
      o.atol = 1e-13;
      o.kernel = Kernel::cpp;
      o.active_constraints = all_names(*model);
      int next = 0;
      const double dt = 0.05;
      auto& out = seen[tree];
      const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
        while (next * dt <= v.t + 1e-12) {
          const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
          out.push_back(smp.derived.segment(i0, 12));
          ++next;
        }
        if (tree) {
          const Eigen::VectorXd qs = v.sample(v.t).q;
          Vector4d p;
          for (int i = 0; i < 4; ++i) p[i] = qs[name_index(names, "p" + std::to_string(i))];
          p0_min = std::min(p0_min, p[0]);
          norm_err = std::max(norm_err, std::abs(p.squaredNorm() - 1));
        }
        return true;
      });
      BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
      BOOST_TEST(out.size() == 41u);
    }
  }
  double err_p = 0, err_a = 0, swing = 0;
  for (std::size_t k = 0; k < seen[true].size() && k < seen[false].size(); ++k) {
    err_p = std::max(err_p, (seen[true][k].head(3) - seen[false][k].head(3)).cwiseAbs().maxCoeff());
    err_a = std::max(err_a, (seen[true][k].tail(9) - seen[false][k].tail(9)).cwiseAbs().maxCoeff());
    swing = std::max(swing, (seen[true][k].head(2) - hub.head(2)).norm());
  }
  BOOST_TEST_MESSAGE("spherical joint, tree against rows over 2 s: origin " << err_p << " m, rotation " << err_a
                     << "; the bob swung out to " << swing << " m from the axis; p0 down to " << p0_min
                     << ", | |p|^2 - 1 | up to " << norm_err);
  BOOST_TEST(swing > 0.05);
  BOOST_TEST(p0_min < 0.0);
  BOOST_TEST(norm_err < 1e-10);
  BOOST_TEST(err_p < 1e-8);
  BOOST_TEST(err_a < 1e-8);
}

// A heavy rigid body on a ball joint fixed in ground (a spherical pendulum with a product of
// inertia, far from the origin), placed by the spherical tree joint and released tumbling: no
// dissipation, so T + V stays at its initial value. Oracle: the energy balance over 10 s, to
// 1e-9 of the largest kinetic energy (rtol 1e-11); the body turns through many relative half
// turns (p0 changes sign several times).
BOOST_AUTO_TEST_CASE(a_body_on_a_spherical_tree_joint_keeps_its_energy_through_many_turns) {
  const std::string text = R"toml([model]
name = "ball_top"
[model.body.ground.markers]
pivot = { at = [-300, 40, 1000], axis = [1, 0, 0], angle = 0.3 }
[model.body.top]
kind = "spatial"
mass = 2.0
inertia = [[0.02, 0.004, 0], [0.004, 0.03, 0.002], [0, 0.002, 0.04]]
markers.tip = [0.01, 0.02, -0.2]
[model.joint.ball]
type = "spherical"
marker1 = "pivot"
body2 = "top"
marker2 = "tip"
coordinates = ["p0", "p1", "p2", "p3"]
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
[model.outputs]
T = "1/2*2.0*(top_vc1^2 + top_vc2^2 + top_vc3^2) + 1/2*(0.02*top_w1^2 + 0.03*top_w2^2 + 0.04*top_w3^2 + 2*0.004*top_w1*top_w2 + 2*0.002*top_w2*top_w3)"
V = "2.0*9.81*top_z"
)toml";
  const auto desc = load_model_text(text, "ball_top.toml");
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  BOOST_REQUIRE(names.size() == 4u);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4), qd = q;
  // Turned 2 rad about (1, 2, 2)/3 relative to the pivot's frame, spinning at 8 rad/s about
  // marker2's (0.3, -0.5, 1)-ish axis: ṗ = ½ Gᵀ(p) ω'.
  const Vector3d u = Vector3d(1, 2, 2) / 3.0, wb(2.4, -4.0, 8.0);
  Vector4d p;
  p << std::cos(1.0), std::sin(1.0) * u;
  Eigen::Matrix<double, 3, 4> G;
  G << -p[1], p[0], p[3], -p[2],  //
      -p[2], -p[3], p[0], p[1],   //
      -p[3], p[2], -p[1], p[0];
  q = p;
  qd = 0.5 * G.transpose() * wb;
  mech::SimulationOptions o;
  o.t_end = 10.0;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.active_constraints = all_names(*model);
  const int iT = output_index(*desc, "T"), iV = output_index(*desc, "V");
  double E0 = NAN, dE = 0, Tmax = 0, prev_p0 = p[0];
  int sign_changes = 0;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const double E = s.derived[iT] + s.derived[iV];
    if (std::isnan(E0)) E0 = E;
    dE = std::max(dE, std::abs(E - E0));
    Tmax = std::max(Tmax, s.derived[iT]);
    const double p0 = s.q[name_index(names, "p0")];
    if ((p0 < 0) != (prev_p0 < 0)) ++sign_changes;
    prev_p0 = p0;
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("body on a spherical tree joint, 10 s: |E - E0| up to " << dE << " J (T up to " << Tmax
                     << " J), p0 changed sign " << sign_changes << " times");
  BOOST_TEST(sign_changes >= 4);
  BOOST_TEST(dE < 1e-9 * Tmax);
}

namespace {

// A puck on a table (marker1, tilted 0.3 rad about x) on a platform a drive spins about the
// vertical, far from the origin; the puck's marker is turned about a skew axis and off its
// axes, its inertia has a product term. By a planar tree joint (the travels x, y along the
// table's axes and the angle th about its normal) or as rows (the puck in Euler parameters, the
// rows z, ax, ay). Outputs: the puck's origin and rotation.
std::string puck_on_table(bool tree) {
  std::string t = R"(
[model]
name = "puck_on_table"
[model.parameters]
w = 2.0
[model.body.ground.markers]
hub = [-300, 700, 20]
[model.body.platform]
kind = "spatial"
mass = 3.0
inertia = [0.2, 0.2, 0.3]
markers.table = { at = [0.2, 0, 0.05], axis = [1, 0, 0], angle = 0.3 }
[model.joint.spin]
type = "revolute"
marker1 = "hub"
body2 = "platform"
coordinates = ["phi"]
[model.joint.motor]
type = "drive"
joint = "spin"
motion = "w*t"
[model.body.puck]
kind = "spatial"
mass = 0.5
inertia = [[4e-3, 0, 0], [0, 5e-3, 1e-3], [0, 1e-3, 7e-3]]
markers.m = { at = [0.01, 0.02, -0.02], axis = [0, 1, 2], angle = -0.7 }
[model.joint.slide]
type = "planar"
body1 = "platform"
marker1 = "table"
body2 = "puck"
marker2 = "m"
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
[model.outputs]
px = "puck_x"
py = "puck_y"
pz = "puck_z"
a11 = "puck_a11"
a12 = "puck_a12"
a13 = "puck_a13"
a21 = "puck_a21"
a22 = "puck_a22"
a23 = "puck_a23"
a31 = "puck_a31"
a32 = "puck_a32"
a33 = "puck_a33"
)";
  if (tree) t.replace(t.find("marker2 = \"m\"\n"), 14, "marker2 = \"m\"\ncoordinates = [\"sx\", \"sy\", \"th\"]\n");
  return t;
}

}  // namespace

// A planar joint between spatial bodies, as a tree joint (the puck placed by its travels and
// angle on the table) and as rows (the puck in Euler parameters, the rows z, ax, ay): an
// independent formulation of the same machine. Released at (0.1, -0.05) m, 0.2 rad on the table,
// moving at (0.3, 0.1) m/s and 2 rad/s relative to it while the platform spins at 2 rad/s, the
// puck slides across the tilted, turning table. Oracle: the two agree on its origin and rotation
// matrix over 1 s to 1e-8 (rtol 1e-11); a drive on the tree joint's angle reports the spatial
// column M_<drive>_z.
BOOST_AUTO_TEST_CASE(planar_joint_between_spatial_bodies_as_tree_joint_and_as_rows_agree) {
  const double w = 2.0, x0 = 0.1, y0 = -0.05, th0 = 0.2, xd0 = 0.3, yd0 = 0.1, thd0 = 2.0;
  const Vector3d hub(-300, 700, 20), m1p(0.2, 0, 0.05), m2p(0.01, 0.02, -0.02);
  const Matrix3d R1 = Eigen::AngleAxisd(0.3, Vector3d::UnitX()).toRotationMatrix();
  const Matrix3d R2 = Eigen::AngleAxisd(-0.7, Vector3d(0, 1, 2).normalized()).toRotationMatrix();
  std::map<bool, std::vector<Eigen::VectorXd>> seen;
  for (const bool tree : {true, false}) {
    BOOST_TEST_CONTEXT((tree ? "tree joint" : "rows")) {
      const auto desc = load_model_text(puck_on_table(tree), "puck_on_table.toml");
      const auto& names = desc->coordinates();
      BOOST_REQUIRE(names.size() == (tree ? 4u : 8u));
      Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
      qd[name_index(names, "phi")] = w;
      if (tree) {
        q[name_index(names, "sx")] = x0;
        q[name_index(names, "sy")] = y0;
        q[name_index(names, "th")] = th0;
        qd[name_index(names, "sx")] = xd0;
        qd[name_index(names, "sy")] = yd0;
        qd[name_index(names, "th")] = thd0;
      } else {
        // The platform's frame is ground's at phi = 0, turning at w about z; marker2's frame is
        // the table's turned by th about its normal: A R2 = R1 Rz(th).
        const Matrix3d A = R1 * Eigen::AngleAxisd(th0, Vector3d::UnitZ()).toRotationMatrix() * R2.transpose();
        const Eigen::Quaterniond e(A);
        const Vector3d P2 = hub + m1p + R1 * Vector3d(x0, y0, 0), r = P2 - A * m2p;
        const Vector3d wp(0, 0, w), omega = wp + R1 * Vector3d(0, 0, thd0);
        const Vector3d vP2 = wp.cross(P2 - hub) + R1 * Vector3d(xd0, yd0, 0);
        const int ix = name_index(names, "puck_x"), ie = name_index(names, "puck_e0");
        q.segment<3>(ix) = r;
        q.segment<4>(ie) << e.w(), e.x(), e.y(), e.z();
        qd.segment<3>(ix) = vP2 + omega.cross(r - P2);
        Eigen::Matrix<double, 3, 4> E;
        E << -e.x(), e.w(), -e.z(), e.y(),  //
            -e.y(), e.z(), e.w(), -e.x(),   //
            -e.z(), -e.y(), e.x(), e.w();
        qd.segment<4>(ie) = 0.5 * E.transpose() * omega;
      }
      const auto model = desc->instantiate({});
      const int i0 = output_index(*desc, "px");
      mech::SimulationOptions o;
      o.t_end = 1.0;
      o.rtol = 1e-11;
      o.atol = 1e-13;
      o.kernel = Kernel::cpp;
      o.active_constraints = all_names(*model);
      int next = 0;
      const double dt = 0.05;
      auto& out = seen[tree];
      const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
        while (next * dt <= v.t + 1e-12) {
          const mech::Sample smp = v.sample(std::max(v.t_prev, next * dt));
          out.push_back(smp.derived.segment(i0, 12));
          ++next;
        }
        return true;
      });
      BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
      BOOST_TEST(out.size() == 21u);
    }
  }
  double err_p = 0, err_a = 0, travel = 0;
  for (std::size_t k = 0; k < seen[true].size() && k < seen[false].size(); ++k) {
    err_p = std::max(err_p, (seen[true][k].head(3) - seen[false][k].head(3)).cwiseAbs().maxCoeff());
    err_a = std::max(err_a, (seen[true][k].tail(9) - seen[false][k].tail(9)).cwiseAbs().maxCoeff());
    travel = std::max(travel, (seen[true][k].head(3) - seen[true][0].head(3)).norm());
  }
  BOOST_TEST_MESSAGE("planar joint, tree against rows over 1 s: origin " << err_p << " m, rotation " << err_a
                     << "; the puck travelled up to " << travel << " m");
  BOOST_TEST(travel > 0.1);
  BOOST_TEST(err_p < 1e-8);
  BOOST_TEST(err_a < 1e-8);
  // A drive on the angle: its reaction is the torque about the table's normal, a spatial column.
  std::string driven = puck_on_table(true);
  driven += "[model.joint.turn]\ntype = \"drive\"\njoint = \"slide\"\ncoordinate = \"th\"\nmotion = \"0.2 + 2*t\"\n";
  const auto d = load_model_text(driven, "puck_driven.toml");
  bool mz = false, fz = false;
  for (const auto& c : d->outputs()) {
    mz = mz || c.name == "M_turn_z";
    fz = fz || c.name == "F_turn_z";
  }
  BOOST_TEST(mz);
  BOOST_TEST(fz);
}

// Drives on a planar tree joint between spatial bodies: a puck (principal inertia, marker2 at its
// centre of mass) on a level table far from the origin, pushed along the table's x at 1 m/s² and
// turned at 3 rad/s² while its y travel is free. Closed forms: the pushing force F_x = m·1 N, the
// driving torque M_z = J3·3 N·m, the free travel stays 0; to 1e-10.
BOOST_AUTO_TEST_CASE(drives_on_a_planar_tree_joint_give_the_force_along_and_the_torque_about_the_table) {
  const double m = 0.8, J3 = 0.05;
  const std::string text = R"([model]
name = "puck_drive"
[model.body.ground.markers]
table = [40, -900, 3]
[model.body.puck]
kind = "spatial"
mass = 0.8
inertia = [0.03, 0.04, 0.05]
[model.joint.slide]
type = "planar"
marker1 = "table"
body2 = "puck"
coordinates = ["sx", "sy", "th"]
[model.joint.push]
type = "drive"
joint = "slide"
coordinate = "sx"
motion = "0.5*t^2"
[model.joint.turn]
type = "drive"
joint = "slide"
coordinate = "th"
motion = "1.5*t^2"
[model.force.gravity]
type = "gravity"
g = [0, 0, -9.81]
)";
  const auto desc = load_model_text(text, "puck_drive.toml");
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3), qd = q;
  mech::SimulationOptions o;
  o.t_end = 1.0;
  o.rtol = o.atol = 1e-12;
  o.active_constraints = all_names(*model);
  const int iF = output_index(*desc, "F_push_x"), iM = output_index(*desc, "M_turn_z");
  double err_F = 0, err_M = 0;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    err_F = std::max(err_F, std::abs(s.derived[iF] - m * 1.0));
    err_M = std::max(err_M, std::abs(s.derived[iM] - J3 * 3.0));
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "sx")] - 0.5) < 1e-10);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "sy")]) < 1e-10);
  BOOST_TEST(std::abs(r.q_end[name_index(names, "th")] - 1.5) < 1e-10);
  BOOST_TEST(err_F < 1e-10);
  BOOST_TEST(err_M < 1e-10);
}

BOOST_AUTO_TEST_CASE(bad_inertia_tensors_are_rejected_naming_the_key) {
  auto load = [](const std::string& inertia) {
    return input_error_of([&] {
      load_model_text("[model]\nname = \"b\"\n[model.body.b]\nkind = \"spatial\"\nmass = 1\ninertia = " +
                          inertia + "\n",
                      "bad.toml");
    });
  };
  BOOST_TEST(contains_all(load("[[1, 0.1, 0], [0.2, 1, 0], [0, 0, 1]]"),
                          {"bad.toml", "model.body.b.inertia", "symmetric"}));
  BOOST_TEST(contains_all(load("[1, 0, 1]"), {"model.body.b.inertia", "positive definite"}));
  BOOST_TEST(contains_all(load("[[1, 2, 0], [2, 1, 0], [0, 0, 1]]"), {"model.body.b.inertia", "positive definite"}));
  BOOST_TEST(contains_all(load("[0.1, 0.1, 1]"), {"model.body.b.inertia", "J_max <= J_a + J_b"}));
  BOOST_TEST(contains_all(load("[1, 1]"), {"model.body.b.inertia", "[J1, J2, J3]"}));
  BOOST_TEST(contains_all(load("2.0"), {"model.body.b.inertia", "symmetric 3x3"}));
  BOOST_TEST(load("[[1, 0.1, 0], [0.1, 1, 0], [0, 0, 1]]").empty());
}

// ---- the 2-D Coulomb cone's rows (issue 22 with docs/switching.md's cone) -------------------

namespace {

// A puck on the plane of a moving body (a spatial `deck`; models/contact/puck_plane_bodies.toml
// has it on ground's): the plane's marker off the deck's origin and turned about a skew axis,
// the puck's marker off its origin and turned too (its axes do not enter the rows).
const char* kPuckOnDeck = R"(
[model]
name = "puck_on_deck"
[model.parameters]
mu_s = 0.4
mu_k = 0.3
[model.body.deck]
kind = "spatial"
mass = 5.0
inertia = [0.4, 0.5, 0.6]
markers.plane = { at = [0.3, -0.2, 0.1], axis = [1, 2, 3], angle = 0.7 }
[model.body.puck]
kind = "spatial"
mass = 0.5
inertia = [2.2e-4, 2.2e-4, 4e-4]
markers.bottom = { at = [0.01, 0.02, -0.01], axis = [0, 1, 1], angle = -0.4 }
[model.joint.table]
type = "point_on_plane"
body1 = "deck"
marker1 = "plane"
body2 = "puck"
marker2 = "bottom"
unilateral = true
mu_static = "mu_s"
mu_kinetic = "mu_k"
)";

// A random orientation and rates (e . e_d = 0) of a spatial body whose 7 coordinates start at i.
void random_body(std::mt19937& rng, const Vector3d& centre, double spread, int i, Eigen::VectorXd& q,
                 Eigen::VectorXd& qd) {
  Vector4d e(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
  e.normalize();
  Vector4d ed(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
  ed -= e * e.dot(ed);
  q.segment<3>(i) = centre + spread * Vector3d(uniform(rng), uniform(rng), uniform(rng));
  q.segment<4>(i + 3) = e;
  qd.segment<3>(i) = 2.0 * Vector3d(uniform(rng), uniform(rng), uniform(rng));
  qd.segment<4>(i + 3) = 2.0 * ed;  // |w| up to ~4 rad/s
}

// The values g q_d + g0 of the velocity-form rows `rows` at (q, q_d).
Eigen::VectorXd row_values(const mech::Model& m, const std::vector<int>& rows, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& qd) {
  const int s = static_cast<int>(rows.size());
  Eigen::MatrixXd g(s, m.n());
  Eigen::VectorXd g0(s), gamma(s);
  m.constraint_rows(rows, 0.3, q, qd, g, g0, gamma);
  return g * qd + g0;
}

// The contact attributes of a Coulomb row pair: both friction rows of the unilateral `gap`,
// Coulomb (not rough), velocity form, with the joint's μ.
void expect_coulomb_pair(const mech::Model& m, const std::string& gap, const std::string& x,
                         const std::string& y, double mu_s, double mu_k) {
  const auto& c = m.constraints();
  const int in = m.constraint_index(gap);
  BOOST_TEST(c[in].contact.unilateral);
  BOOST_TEST(!c[in].contact.is_friction());
  for (const std::string& r : {x, y}) {
    BOOST_TEST_CONTEXT(r) {
      const mech::ConstraintInfo& ci = c[m.constraint_index(r)];
      BOOST_TEST(static_cast<int>(ci.kind) == static_cast<int>(mech::ConstraintKind::velocity));
      BOOST_TEST(ci.contact.is_coulomb());
      BOOST_TEST(!ci.contact.rough);
      BOOST_TEST(!ci.contact.unilateral);
      BOOST_TEST(ci.contact.friction_of == in);
      BOOST_TEST(ci.contact.mu_static == mu_s);
      BOOST_TEST(ci.contact.mu_kinetic == mu_k);
    }
  }
}

}  // namespace

// A point_on_plane with mu_static (models/contact/puck_plane_bodies.toml on ground's plane,
// moved to (1200, -900, 600) m and turned by psi = 0.5 about its normal; kPuckOnDeck on a
// tumbling deck ~1e3 m from the origin): its rows table_slide_x, table_slide_y are the contact's
// two Coulomb rows (friction = table_z, mu_s = 0.4, mu_k = 0.3), and at 20 random states each
// they equal the closed form of the sliding velocity along u1 and v1: with P2 = r2 + A2 p2
// (marker2's origin) v_rel = r2_d + w2 x (A2 p2) - (r1_d + w1 x (P2 - r1)), w = 2 E(e) e_d,
// u1, v1 the columns of A1 R1 (Eigen's rotations, not the joint's texts). The states lie ~1e3 m
// from the origin, where each position carries a rounding of 1e3 * 1.1e-16 m that the rows
// multiply by |w| (a few rad/s) and by the axes' entries: 1e-12 of the velocities' scale
// (|v_P2| + |v_1|) bounds it with a margin. The reaction F_table_x, _y, _z (joint frame) is
// (lambda_slide_x, lambda_slide_y, lambda_z) and M_table is zero, for random multipliers.
BOOST_AUTO_TEST_CASE(point_on_plane_friction_rows_are_the_sliding_velocity_along_the_planes_axes) {
  for (const bool deck : {false, true}) {
    BOOST_TEST_CONTEXT((deck ? "on a moving deck" : "on ground's plane")) {
      const Vector3d X0(1200.0, -900.0, 600.0);
      const auto desc = deck ? load_model_text(kPuckOnDeck, "puck_on_deck.toml")
                             : load_model_file(model_path("contact/puck_plane_bodies.toml"));
      const auto model = deck ? desc->instantiate({})
                              : desc->instantiate({{"X0", X0[0]}, {"Y0", X0[1]}, {"Z0", X0[2]}});
      expect_coulomb_pair(*model, "table_z", "table_slide_x", "table_slide_y", 0.4, 0.3);
      const auto& names = model->coordinates();
      const int ip = name_index(names, "puck_x"), id = deck ? name_index(names, "deck_x") : -1;
      const Vector3d p1 = deck ? Vector3d(0.3, -0.2, 0.1) : Vector3d::Zero();
      const Matrix3d R1 = deck ? Matrix3d(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()))
                               : Matrix3d(Eigen::AngleAxisd(0.5, Vector3d::UnitZ()));
      const Vector3d p2 = deck ? Vector3d(0.01, 0.02, -0.01) : Vector3d(0, 0, 0);  // the puck's centre
      const std::vector<int> rows = indices(*model, {"table_slide_x", "table_slide_y"});
      std::mt19937 rng(deck ? 41 : 40);
      double worst = 0, worst_F = 0;
      for (int k = 0; k < 20; ++k) {
        Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = q;
        Vector3d r1 = X0, v1 = Vector3d::Zero(), w1 = Vector3d::Zero();
        Matrix3d A1 = Matrix3d::Identity();
        if (deck) {
          random_body(rng, Vector3d(1000.0, -700.0, 400.0), 0.5, id, q, qd);
          r1 = q.segment<3>(id);
          A1 = A_of(q.segment<4>(id + 3));
          w1 = 2 * E_of(q.segment<4>(id + 3)) * qd.segment<4>(id + 3);
          v1 = qd.segment<3>(id);
        }
        const Vector3d P1 = r1 + A1 * p1;
        random_body(rng, P1, 0.1, ip, q, qd);
        const Vector4d e2 = q.segment<4>(ip + 3);
        const Matrix3d A2 = A_of(e2);
        const Vector3d w2 = 2 * E_of(e2) * qd.segment<4>(ip + 3);
        const Vector3d P2 = q.segment<3>(ip) + A2 * p2;
        const Vector3d vP2 = qd.segment<3>(ip) + w2.cross(A2 * p2);
        const Vector3d vB1 = v1 + w1.cross(P2 - r1);  // body1's material point at P2
        const Matrix3d U = A1 * R1;
        const Eigen::Vector2d expected(U.col(0).dot(vP2 - vB1), U.col(1).dot(vP2 - vB1));
        const Eigen::VectorXd got = row_values(*model, rows, q, qd);
        worst = std::max(worst, (got - expected).cwiseAbs().maxCoeff() / (vP2.norm() + vB1.norm()));
        // The reaction in the joint frame, from random multipliers of every row.
        const std::vector<int> all = all_rows(*model);
        Eigen::VectorXd lambda(static_cast<Eigen::Index>(all.size())), out;
        for (auto& l : lambda) l = 10.0 * uniform(rng);
        const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model->n());
        model->derived_with_multipliers(0.3, q, qd, zero, zero, all, lambda, out);
        auto column = [&](const std::string& c) { return out[name_index(model->derived_names(), c)]; };
        auto lambda_of = [&](const std::string& r) { return lambda[model->constraint_index(r)]; };
        for (double d : {column("F_table_x") - lambda_of("table_slide_x"), column("F_table_y") - lambda_of("table_slide_y"),
                         column("F_table_z") - lambda_of("table_z"), column("M_table_x"), column("M_table_y"),
                         column("M_table_z")})
          worst_F = std::max(worst_F, std::abs(d) / 10.0);
      }
      BOOST_TEST_MESSAGE((deck ? "deck" : "ground") << ": slide rows against the closed form, worst " << worst
                         << " of |v|; reaction against the multipliers, worst " << worst_F << " of |lambda|");
      BOOST_TEST(worst < 1e-12);
      BOOST_TEST(worst_F < 1e-14);
    }
  }
}

// A wheel with mu_static (models/contact/coin_friction_bodies.toml on a plane; wheel_in_bowl's
// wheel on a sphere, inside and outside, made unilateral with mu_static = 0.5, mu_kinetic =
// 0.25): its no-slip rows x, y are the contact's two Coulomb rows (not rough; the rolling coin
// without mu_static keeps rough ones), and they are the sliding velocity of the wheel's material
// contact point along two orthonormal tangents. The closed form, at 20 random states ~1e3 m from
// the origin: a = A e_z (the axis), the contact point C + rho; the plane: rho = -r (n - (n.a) a)
// / |n x a|, tangents x, y of the floor marker (ground's); the sphere (centre S): d = C - S,
// d_p = d - (d.a) a, rho = -/+ r d_p/|d_p| (outside/inside), nu = +/-(d + rho)/|d + rho|,
// t1 = a x rho / r, t2 = nu x t1, checked orthonormal and normal to nu here; the rows against
// t.(C_d + w x rho), 1e-12 of |C_d| + |w| r (positions ~1e3 m rounded to 1e-13 m, as above).
BOOST_AUTO_TEST_CASE(wheel_friction_rows_are_the_contact_points_sliding_velocity_along_orthonormal_tangents) {
  {
    const auto rough = load_model_file(model_path("contact/coin_rolling_bodies.toml"))->instantiate({});
    for (const char* r : {"bounce_x", "bounce_y"}) {
      const auto& c = rough->constraints()[rough->constraint_index(r)].contact;
      BOOST_TEST((c.is_friction() && c.rough && !c.is_coulomb()), r);
    }
  }
  struct Case {
    std::string name;
    std::string text;
    bool sphere, inside;
  };
  std::string bowl = model_text("wheel_in_bowl_bodies.toml");
  const std::string inside_key = "inside = true\n";
  bowl.replace(bowl.find(inside_key), inside_key.size(),
               "inside = true\nunilateral = true\nmu_static = 0.5\nmu_kinetic = 0.25\n");
  std::string ball = bowl;
  ball.replace(ball.find(inside_key), inside_key.size(), "inside = false\n");
  const std::vector<Case> cases{{"coin_friction_bodies", model_text("contact/coin_friction_bodies.toml"), false, false},
                                {"bowl", bowl, true, true},
                                {"ball", ball, true, false}};
  const Vector3d S(1100.0, -800.0, 500.0);
  for (const Case& c : cases) {
    BOOST_TEST_CONTEXT(c.name) {
      const auto desc = load_model_text(c.text, c.name + ".toml");
      const auto model = desc->instantiate({{"X0", S[0]}, {"Y0", S[1]}, {"Z0", S[2]}});
      const std::string j = c.sphere ? "roll" : "bounce";
      const std::string body = c.sphere ? "wheel" : "coin";
      const double r = c.sphere ? 0.2 : 0.012, R = 1.0;
      expect_coulomb_pair(*model, j + "_n", j + "_x", j + "_y", c.sphere ? 0.5 : 0.3, c.sphere ? 0.25 : 0.2);
      const int ib = name_index(model->coordinates(), body + "_x");
      const std::vector<int> rows = indices(*model, {j + "_x", j + "_y"});
      std::mt19937 rng(43);
      double worst = 0, ortho = 0;
      for (int k = 0; k < 20; ++k) {
        Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = q;
        Vector3d dir(uniform(rng), uniform(rng), uniform(rng));
        dir.normalize();
        const Vector3d centre = c.sphere ? Vector3d(S + (c.inside ? R - r : R + r) * dir) : Vector3d(S + Vector3d(0, 0, r));
        random_body(rng, centre, 0.3 * r, ib, q, qd);
        const Vector3d C = q.segment<3>(ib), Cd = qd.segment<3>(ib);
        const Vector4d e = q.segment<4>(ib + 3);
        const Vector3d a = A_of(e).col(2), w = 2 * E_of(e) * qd.segment<4>(ib + 3);
        Vector3d rho, t1, t2;
        if (!c.sphere) {
          const Vector3d n = Vector3d::UnitZ();
          rho = -r * (n - n.dot(a) * a) / n.cross(a).norm();
          t1 = Vector3d::UnitX();
          t2 = Vector3d::UnitY();
        } else {
          const Vector3d d = C - S, dp = d - d.dot(a) * a;
          rho = (c.inside ? r : -r) * dp / dp.norm();
          const Vector3d nu = (c.inside ? -1.0 : 1.0) * (d + rho).normalized();
          t1 = a.cross(rho) / r;
          t2 = nu.cross(t1);
          for (double v : {t1.norm() - 1, t2.norm() - 1, t1.dot(t2), t1.dot(nu), t2.dot(nu)})
            ortho = std::max(ortho, std::abs(v));
        }
        const Vector3d vc = Cd + w.cross(rho);  // the wheel's material point at the contact
        const Eigen::Vector2d expected(t1.dot(vc), t2.dot(vc));
        worst = std::max(worst, (row_values(*model, rows, q, qd) - expected).cwiseAbs().maxCoeff() /
                                    (Cd.norm() + w.norm() * r));
      }
      BOOST_TEST_MESSAGE(c.name << ": x, y rows against the closed-form sliding velocity, worst " << worst
                         << " of |v|; tangents orthonormal and normal to nu to " << ortho);
      BOOST_TEST(worst < 1e-12);
      BOOST_TEST(ortho < 1e-14);
    }
  }
}

// ---- the ball joint (a sphere on a plane) ---------------------------------------------------

namespace {

// A ball on a tumbling deck: the plane's marker off the deck's origin and turned about a skew
// axis; the ball's centre (marker2) off the ball body's origin and turned too (marker2's axes do
// not enter a ball's rows). Bilateral: no contact keys.
const char* kBallOnDeck = R"(
[model]
name = "ball_on_deck"
[model.body.deck]
kind = "spatial"
mass = 5.0
inertia = [0.4, 0.5, 0.6]
markers.plane = { at = [0.3, -0.2, 0.1], axis = [1, 2, 3], angle = 0.7 }
[model.body.ball]
kind = "spatial"
mass = 0.3
inertia = [2e-4, 2e-4, 2e-4]
markers.centre = { at = [0.01, 0.02, -0.01], axis = [0, 1, 1], angle = -0.4 }
[model.joint.roll]
type = "ball"
body1 = "deck"
marker1 = "plane"
body2 = "ball"
marker2 = "centre"
radius = 0.04
)";

// The same ball on ground's plane, its marker at (X0, Y0, Z0) turned by 0.5 rad about (1, -2, 2),
// a contact with the 2-D cone (mu_s = 0.4, mu_k = 0.3).
const char* kBallOnGround = R"(
[model]
name = "ball_on_ground"
[model.parameters]
X0 = 400.0
Y0 = -300.0
Z0 = 120.0
[model.body.ground.markers]
plane = { at = ["X0", "Y0", "Z0"], axis = [1, -2, 2], angle = 0.5 }
[model.body.ball]
kind = "spatial"
mass = 0.3
inertia = [2e-4, 2e-4, 2e-4]
markers.centre = { at = [0.01, 0.02, -0.01], axis = [0, 1, 1], angle = -0.4 }
[model.joint.roll]
type = "ball"
marker1 = "plane"
body2 = "ball"
marker2 = "centre"
radius = 0.04
unilateral = true
restitution = 0.5
mu_static = 0.4
mu_kinetic = 0.3
)";

}  // namespace

// The ball joint's rows (docs/bodies-spatial.md "Joints") against their definition computed here
// with Eigen from the coordinates alone, at 20 random states each, for a ball on ground's plane
// (turned about a skew axis, 500 m from the origin, with mu_static: rows x, y are the contact's
// two Coulomb rows) and on a tumbling deck (bilateral): with U = A1 R1 (u1, v1, w1 its columns),
// P1 = r1 + A1 p1, P2 = r2 + A2 p2 (the centre) and C = P2 - R w1 (the contact point),
//   n = (P2 - P1).w1 - R,  x = u1.(v_C - v_B1(C)),  y = v1.(v_C - v_B1(C)),
// v_C = r2_d + w2 x (C - r2) (the ball's material point at C), v_B1(C) = r1_d + w1 x (C - r1)
// (body1's; 0 on ground), w = 2 E(e) e_d. Also the n row's rate g q_d against
// d/dt n = (v_P2 - v_P1).w1 + (P2 - P1).(w_1 x w1), and the reaction from random multipliers:
// F_roll = (lambda_x, lambda_y, lambda_n) (joint frame) acting at C, so M_roll (about the centre)
// = (-R e_z) x F = (R lambda_y, -R lambda_x, 0). Tolerances: positions ~500 m from the origin
// carry a rounding of 500 * 1.1e-16 = 6e-14 m, which the gap row sees directly (1e-12 m) and the
// velocity rows through |w| <= 4 rad/s and the axes (1e-12 of the velocities' scale); the
// reaction is a product of the multipliers with exact axes, to 1e-14 of |lambda|.
// Without mu_static a unilateral ball's rows x, y are rough rows (as the wheel's).
BOOST_AUTO_TEST_CASE(ball_rows_are_the_gap_and_the_contact_points_sliding_velocity_along_the_planes_axes) {
  {
    std::string text = kBallOnGround;
    text.replace(text.find("mu_static = 0.4\n"), 16, "");
    text.replace(text.find("mu_kinetic = 0.3\n"), 17, "");
    const auto rough = load_model_text(text, "ball_rough.toml")->instantiate({});
    for (const char* r : {"roll_x", "roll_y"}) {
      const auto& c = rough->constraints()[rough->constraint_index(r)].contact;
      BOOST_TEST((c.is_friction() && c.rough && !c.is_coulomb()), r);
    }
  }
  const double R = 0.04;
  for (const bool deck : {false, true}) {
    BOOST_TEST_CONTEXT((deck ? "on a tumbling deck" : "on ground's plane")) {
      const Vector3d X0(400.0, -300.0, 120.0);
      const auto desc = load_model_text(deck ? kBallOnDeck : kBallOnGround, deck ? "ball_on_deck.toml" : "ball_on_ground.toml");
      const auto model = desc->instantiate({});
      if (!deck) {
        expect_coulomb_pair(*model, "roll_n", "roll_x", "roll_y", 0.4, 0.3);
        BOOST_TEST(model->constraints()[model->constraint_index("roll_n")].contact.restitution == 0.5);
      } else {
        for (const char* r : {"roll_n", "roll_x", "roll_y"}) {
          const auto& c = model->constraints()[model->constraint_index(r)].contact;
          BOOST_TEST((!c.unilateral && !c.is_friction()), r);
        }
      }
      const auto& names = model->coordinates();
      const int ib = name_index(names, "ball_x"), id = deck ? name_index(names, "deck_x") : -1;
      const Vector3d p1 = deck ? Vector3d(0.3, -0.2, 0.1) : Vector3d::Zero();
      const Matrix3d R1 = deck ? Matrix3d(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()))
                               : Matrix3d(Eigen::AngleAxisd(0.5, Vector3d(1, -2, 2).normalized()));
      const Vector3d p2(0.01, 0.02, -0.01);
      const int in = model->constraint_index("roll_n");
      const std::vector<int> rows = indices(*model, {"roll_n", "roll_x", "roll_y"});
      std::mt19937 rng(deck ? 45 : 44);
      double worst_gap = 0, worst_rate = 0, worst = 0, worst_F = 0;
      for (int k = 0; k < 20; ++k) {
        Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = q;
        Vector3d r1 = X0, v1 = Vector3d::Zero(), w1 = Vector3d::Zero();
        Matrix3d A1 = Matrix3d::Identity();
        if (deck) {
          random_body(rng, X0, 0.5, id, q, qd);
          r1 = q.segment<3>(id);
          A1 = A_of(q.segment<4>(id + 3));
          w1 = 2 * E_of(q.segment<4>(id + 3)) * qd.segment<4>(id + 3);
          v1 = qd.segment<3>(id);
        }
        const Matrix3d U = A1 * R1;
        const Vector3d P1 = r1 + A1 * p1, n = U.col(2);
        random_body(rng, P1 + R * n, 0.1, ib, q, qd);
        const Vector3d r2 = q.segment<3>(ib);
        const Matrix3d A2 = A_of(q.segment<4>(ib + 3));
        const Vector3d w2 = 2 * E_of(q.segment<4>(ib + 3)) * qd.segment<4>(ib + 3);
        const Vector3d P2 = r2 + A2 * p2, C = P2 - R * n;
        const Vector3d vP2 = qd.segment<3>(ib) + w2.cross(A2 * p2), vP1 = v1 + w1.cross(P1 - r1);
        const Vector3d vC = qd.segment<3>(ib) + w2.cross(C - r2);
        const Vector3d vB1 = v1 + w1.cross(C - r1);  // body1's material point at C
        worst_gap = std::max(worst_gap, std::abs(model->position_residual(in, 0.3, q) - ((P2 - P1).dot(n) - R)));
        const Eigen::VectorXd got = row_values(*model, rows, q, qd);
        const double rate = (vP2 - vP1).dot(n) + (P2 - P1).dot(w1.cross(n));
        const double scale = vP2.norm() + vP1.norm() + vC.norm() + vB1.norm();
        worst_rate = std::max(worst_rate, std::abs(got[0] - rate) / scale);
        const Eigen::Vector2d expected(U.col(0).dot(vC - vB1), U.col(1).dot(vC - vB1));
        worst = std::max(worst, (got.tail<2>() - expected).cwiseAbs().maxCoeff() / scale);
        // The reaction in the joint frame, from random multipliers of every row.
        const std::vector<int> all = all_rows(*model);
        Eigen::VectorXd lambda(static_cast<Eigen::Index>(all.size())), out;
        for (auto& l : lambda) l = 10.0 * uniform(rng);
        const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model->n());
        model->derived_with_multipliers(0.3, q, qd, zero, zero, all, lambda, out);
        auto column = [&](const std::string& c) { return out[name_index(model->derived_names(), c)]; };
        auto lambda_of = [&](const std::string& r) { return lambda[model->constraint_index(r)]; };
        const double lx = lambda_of("roll_x"), ly = lambda_of("roll_y"), ln = lambda_of("roll_n");
        for (double d : {column("F_roll_x") - lx, column("F_roll_y") - ly, column("F_roll_z") - ln,
                         column("M_roll_x") - R * ly, column("M_roll_y") + R * lx, column("M_roll_z")})
          worst_F = std::max(worst_F, std::abs(d) / 10.0);
      }
      BOOST_TEST_MESSAGE((deck ? "deck" : "ground") << ": gap row " << worst_gap << " m, its rate " << worst_rate
                         << " and the x, y rows " << worst << " of |v| against the closed form; reaction "
                         << worst_F << " of |lambda|");
      BOOST_TEST(worst_gap < 1e-12);
      BOOST_TEST(worst_rate < 1e-12);
      BOOST_TEST(worst < 1e-12);
      BOOST_TEST(worst_F < 1e-14);
    }
  }
}

// A homogeneous ball (J = 2/5 m R^2) rolling without slip on a turntable spun at a constant
// Omega about ground z (models/ball_turntable_bodies.toml: a revolute tree joint driven by
// th = Omega t; the ball joint bilateral; the table's axis at (400, -300, 120) m).
// The closed form: with F the table's horizontal force on the ball at the contact (-R z from the
// centre; the normal force m g balances gravity, the centre staying at the height R),
//   m dv/dt = F,   J dw/dt = (-R z) x F,
// and no slip, v + w x (-R z) = Omega z x r (r the centre's horizontal position from the axis,
// the contact point's too). Differentiating the last, with dr/dt = v and
// (dw/dt) x (-R z) = (R^2 / J) F for a horizontal F:
//   dv/dt (1 + m R^2 / J) = Omega z x v,   so   dv/dt = (2/7) Omega z x v.
// v turns at w_c = (2/7) Omega at constant speed: the centre runs round a circle at w_c, centred
// at c = r0 + z x v0 / w_c, radius |v0| / w_c. The spin follows from no slip,
// w_h = (Omega r + z x v) / R, and w_z is constant (the contact force's moment about the centre
// is horizontal); the friction force is m w_c z x v, magnitude m w_c |v|. Its kinetic energy is
// not conserved (the drive does work on the table), so the check is the trajectory itself and
// the closed-form invariant |r - c| = |v0| / w_c.
// Omega = 7 rad/s (w_c = 2 rad/s) from r0 = (0.3, 0, 0) m, v0 = (0, 0.2, 0) m/s, w_z = 5 rad/s,
// over three turns of the centre (3 pi s; the table turns 10.5 times), rtol 1e-10: the centre to
// 1e-8 m (the integration's accuracy accumulated over 3 pi s: measured in the test's message),
// |r - c| to 1e-8 m, w to 2e-6 rad/s (of 38: w_h = (Omega r + z x v) / R carries the centre's
// error times Omega / R = 140 /s), the reaction (F_roll in the table's axes, the joint frame, and
// M_roll = (-R z) x F about the centre) to 1e-8 N and 1e-9 N m (of 0.08 N, 4e-3 N m), the normal
// force m g to 1e-9 N. Measured (Release): centre 2.4e-9 m, w 3.5e-7 rad/s, F 5.9e-9 N.
BOOST_AUTO_TEST_CASE(ball_on_a_turntable_circles_at_two_sevenths_of_the_tables_rate) {
  const double m = 0.2, R = 0.05, g = 9.81, Omega = 7.0, wc = 2.0 / 7.0 * Omega, wz = 5.0;
  const Vector3d X0(400.0, -300.0, 120.0), r0(0.3, 0.0, 0.0), v0(0.0, 0.2, 0.0), z = Vector3d::UnitZ();
  const Vector3d c = r0 + z.cross(v0) / wc;  // the circle's centre, from the axis
  const double radius = v0.norm() / wc;
  const auto desc = load_model_file(model_path("ball_turntable_bodies.toml"));
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
  const int ith = name_index(names, "th"), ib = name_index(names, "ball_x");
  const Vector4d e0(1, 0, 0, 0);
  const Vector3d w0 = (Omega * r0 + z.cross(v0)) / R + wz * z;
  q.segment<3>(ib) = X0 + r0 + R * z;
  q.segment<4>(ib + 3) = e0;
  qd[ith] = Omega;
  qd.segment<3>(ib) = v0;
  qd.segment<4>(ib + 3) = 0.5 * E_of(e0).transpose() * w0;
  const auto model = desc->instantiate({}, q);
  const int iF = output_index(*desc, "F_roll_x"), iM = output_index(*desc, "M_roll_x"), iN = output_index(*desc, "normal");
  const double T = 3 * 2 * M_PI / wc, dt = 0.05;
  mech::SimulationOptions o;
  o.t_end = T;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_names(*model);
  double err_x = 0, err_z = 0, err_circle = 0, err_w = 0, err_F = 0, err_M = 0, err_N = 0, turned = 0;
  int next = 0;
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    while (next * dt <= v.t + 1e-12) {
      const mech::Sample s = v.sample(std::max(v.t_prev, next * dt));
      const double t = s.t;
      const Matrix3d Rc = Eigen::AngleAxisd(wc * t, z).toRotationMatrix();
      const Vector3d rel = Rc * (r0 - c), rt = c + rel, vt = wc * z.cross(rel);
      const Vector3d x = s.q.segment<3>(ib) - X0;
      err_x = std::max(err_x, (x.head<2>() - rt.head<2>()).cwiseAbs().maxCoeff());
      err_z = std::max(err_z, std::abs(x[2] - R));
      err_circle = std::max(err_circle, std::abs((x - c).head<2>().norm() - radius));
      const Vector3d w = 2 * E_of(s.q.segment<4>(ib + 3)) * s.qd.segment<4>(ib + 3);
      err_w = std::max(err_w, (w - ((Omega * rt + z.cross(vt)) / R + wz * z)).cwiseAbs().maxCoeff());
      // The table's force on the ball, in the table's axes (turned by th = Omega t), and its
      // moment about the centre.
      const Matrix3d Rt = Eigen::AngleAxisd(Omega * t, z).toRotationMatrix();
      const Vector3d F = Rt.transpose() * (m * wc * z.cross(vt) + m * g * z);
      const Vector3d M = (-R * z).cross(F);
      err_F = std::max(err_F, (s.derived.segment<3>(iF) - F).cwiseAbs().maxCoeff());
      err_M = std::max(err_M, (s.derived.segment<3>(iM) - M).cwiseAbs().maxCoeff());
      err_N = std::max(err_N, std::abs(s.derived[iN] - m * g));
      turned = wc * t;
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("ball on a turntable over " << turned / (2 * M_PI) << " turns of its centre: centre "
                     << err_x << " m (height " << err_z << " m), |r - c| - |v0|/w_c " << err_circle
                     << " m, w " << err_w << " rad/s, F_roll " << err_F << " N, M_roll " << err_M
                     << " N m, normal " << err_N << " N");
  BOOST_TEST(turned > 3 * 2 * M_PI - 0.1);
  BOOST_TEST(err_x < 1e-8);
  BOOST_TEST(err_z < 1e-11);
  BOOST_TEST(err_circle < 1e-8);
  BOOST_TEST(err_w < 2e-6);
  BOOST_TEST(err_F < 1e-8);
  BOOST_TEST(err_M < 1e-9);
  BOOST_TEST(err_N < 1e-9);
}

// ---- the ball joint on a sphere (surface = "sphere", outside or inside a bowl) ---------------

// The ball joint's sphere rows (docs/bodies-spatial.md "Joints") against their definition
// computed here with Eigen, at 20 random states each, outside and inside a sphere of radius
// Rs = 0.5 m centred at marker1: on ground (the marker at (300, -200, 80) m turned by 0.5 rad
// about (1, -2, 2), with mu_static: rows x, y the contact's Coulomb rows) and on a tumbling deck
// (bilateral). With d = P2 - P1, nu = d/|d|, n_hat = +nu outside, -nu inside:
//   n = |d| - (Rs + R) outside, (Rs - R) - |d| inside;  its rate +/- nu.(v_P2 - v_P1);
//   x = t1.(v_C - v_B1(C)), y = t2.(...), C = P2 - R n_hat the ball's material point,
// where (t1, t2) = Q (u1, v1), Q = Eigen's Quaterniond::FromTwoVectors(w1, n_hat) (the least
// rotation taking w1 to n_hat: an independent construction of the joint's two-reflection
// formula); the reaction F = lambda_n n_hat + lambda_x t1 + lambda_y t2 at C, in the joint frame
// (marker1's axes U): U^T F and U^T ((-R n_hat) x F). States with 1 + w1.n_hat < 0.1 are drawn
// again (the tangents' one singular point is n_hat = -w1). Tolerances: positions ~370 m from the
// origin carry a rounding of 370 * 1.1e-16 = 4e-14 m, which the gap sees directly (1e-12 m); n_hat
// = d/|d| with |d| ~ 0.5 m carries 1e-13 relative, amplified up to 10x by 1/(1 + w1.n_hat) in the
// tangents, so the x, y rows and the reaction are held to 1e-11 of the velocities' scale and of
// |lambda| (the rate of n, free of the tangents, to 1e-12).
BOOST_AUTO_TEST_CASE(ball_on_a_sphere_rows_are_the_gap_and_the_sliding_velocity_along_the_least_rotated_tangents) {
  const double R = 0.04, Rs = 0.5;
  const Vector3d X0(300.0, -200.0, 80.0);
  for (const bool deck : {false, true}) {
    for (const bool inside : {false, true}) {
      BOOST_TEST_CONTEXT((deck ? "on a tumbling deck, " : "on ground, ") << (inside ? "inside" : "outside")) {
        std::string text = deck ? kBallOnDeck : kBallOnGround;
        if (!deck) {
          text.replace(text.find("X0 = 400.0"), 10, "X0 = 300.0");
          text.replace(text.find("Y0 = -300.0"), 11, "Y0 = -200.0");
          text.replace(text.find("Z0 = 120.0"), 10, "Z0 = 80.0");
        }
        text += "surface = \"sphere\"\nsphere_radius = 0.5\n";
        if (inside) text += "inside = true\n";
        const auto model = load_model_text(text, "ball_on_sphere.toml")->instantiate({});
        if (!deck) expect_coulomb_pair(*model, "roll_n", "roll_x", "roll_y", 0.4, 0.3);
        const auto& names = model->coordinates();
        const int ib = name_index(names, "ball_x"), id = deck ? name_index(names, "deck_x") : -1;
        const Vector3d p1 = deck ? Vector3d(0.3, -0.2, 0.1) : Vector3d::Zero();
        const Matrix3d R1 = deck ? Matrix3d(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()))
                                 : Matrix3d(Eigen::AngleAxisd(0.5, Vector3d(1, -2, 2).normalized()));
        const Vector3d p2(0.01, 0.02, -0.01);
        const int in = model->constraint_index("roll_n");
        const std::vector<int> rows = indices(*model, {"roll_n", "roll_x", "roll_y"});
        std::mt19937 rng(deck ? 47 : 46);
        double worst_gap = 0, worst_rate = 0, worst = 0, worst_F = 0;
        int k = 0, upper = 0, lower = 0;
        while (k < 20) {
          Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = q;
          Vector3d r1 = X0, v1 = Vector3d::Zero(), wb1 = Vector3d::Zero();
          Matrix3d A1 = Matrix3d::Identity();
          if (deck) {
            random_body(rng, X0, 0.5, id, q, qd);
            r1 = q.segment<3>(id);
            A1 = A_of(q.segment<4>(id + 3));
            wb1 = 2 * E_of(q.segment<4>(id + 3)) * qd.segment<4>(id + 3);
            v1 = qd.segment<3>(id);
          }
          const Matrix3d U = A1 * R1;
          const Vector3d P1 = r1 + A1 * p1;
          // The centre at a random direction from S, at the touching distance plus up to 1 cm.
          const Vector3d dir = Vector3d(uniform(rng), uniform(rng), uniform(rng)).normalized();
          const double L = (inside ? Rs - R : Rs + R) + 0.01 * uniform(rng);
          random_body(rng, X0, 0.0, ib, q, qd);
          const Matrix3d A2 = A_of(q.segment<4>(ib + 3));
          q.segment<3>(ib) = P1 + L * dir - A2 * p2;
          const Vector3d r2 = q.segment<3>(ib);
          const Vector3d w2 = 2 * E_of(q.segment<4>(ib + 3)) * qd.segment<4>(ib + 3);
          const Vector3d P2 = r2 + A2 * p2, d = P2 - P1, nu = d.normalized();
          const Vector3d n_hat = inside ? Vector3d(-nu) : nu, C = P2 - R * n_hat;
          const Vector3d vP2 = qd.segment<3>(ib) + w2.cross(A2 * p2), vP1 = v1 + wb1.cross(P1 - r1);
          const Vector3d vC = qd.segment<3>(ib) + w2.cross(C - r2), vB1 = v1 + wb1.cross(C - r1);
          const double gap = inside ? (Rs - R) - d.norm() : d.norm() - (Rs + R);
          worst_gap = std::max(worst_gap, std::abs(model->position_residual(in, 0.3, q) - gap));
          const Eigen::VectorXd got = row_values(*model, rows, q, qd);
          const double rate = (inside ? -1.0 : 1.0) * nu.dot(vP2 - vP1);
          const double scale = vP2.norm() + vP1.norm() + vC.norm() + vB1.norm();
          worst_rate = std::max(worst_rate, std::abs(got[0] - rate) / scale);
          // The chart of w1·n̂ > −1/2 turns (u1, v1, w1) onto n̂, the other one the right-handed
          // (u1, −v1, −w1).
          const double sg = U.col(2).dot(n_hat) > -0.5 ? 1.0 : -1.0;
          const Eigen::Quaterniond Q = Eigen::Quaterniond::FromTwoVectors(sg * U.col(2), n_hat);
          const Vector3d t1 = Q * U.col(0), t2 = sg * (Q * U.col(1));
          ++(sg > 0 ? upper : lower);
          const Eigen::Vector2d expected(t1.dot(vC - vB1), t2.dot(vC - vB1));
          worst = std::max(worst, (got.tail<2>() - expected).cwiseAbs().maxCoeff() / scale);
          const std::vector<int> all = all_rows(*model);
          Eigen::VectorXd lambda(static_cast<Eigen::Index>(all.size())), out;
          for (auto& l : lambda) l = 10.0 * uniform(rng);
          const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model->n());
          model->derived_with_multipliers(0.3, q, qd, zero, zero, all, lambda, out);
          auto column = [&](const std::string& c) { return out[name_index(model->derived_names(), c)]; };
          auto lambda_of = [&](const std::string& r) { return lambda[model->constraint_index(r)]; };
          const Vector3d F = lambda_of("roll_n") * n_hat + lambda_of("roll_x") * t1 + lambda_of("roll_y") * t2;
          const Vector3d Fj = U.transpose() * F, Mj = U.transpose() * (-R * n_hat).cross(F);
          const Vector3d Fgot(column("F_roll_x"), column("F_roll_y"), column("F_roll_z"));
          const Vector3d Mgot(column("M_roll_x"), column("M_roll_y"), column("M_roll_z"));
          worst_F = std::max(worst_F, std::max((Fgot - Fj).cwiseAbs().maxCoeff(), (Mgot - Mj).cwiseAbs().maxCoeff() / R) / 10.0);
          ++k;
        }
        BOOST_TEST_MESSAGE((deck ? "deck" : "ground") << (inside ? " inside" : " outside") << ": gap row " << worst_gap
                           << " m, its rate " << worst_rate << " and the x, y rows " << worst
                           << " of |v| against Eigen; reaction " << worst_F << " of |lambda|; " << upper
                           << " states with w1.n > -1/2, " << lower << " below");
        BOOST_TEST(upper > 0);
        BOOST_TEST(lower > 0);
        BOOST_TEST(worst_gap < 1e-12);
        BOOST_TEST(worst_rate < 1e-12);
        BOOST_TEST(worst < 1e-11);
        BOOST_TEST(worst_F < 1e-11);
      }
    }
  }
}

namespace {
// models/ball_bowl_bodies.toml's ball (m, r) and bowl (radius Rb, centre S).
constexpr double kBowlM = 0.5, kBowlBallR = 0.1, kBowlR = 1.0, kBowlG = 9.81, kBowlL = kBowlR - kBowlBallR;
const Vector3d kBowlS(300.0, -200.0, 80.0);

// The ball released at rest th0 from the bowl's bottom in the plane y = Y0 (rtol 1e-11, atol
// 1e-13), sampled every dt: the upward zero crossings of x − X0 (linear between samples), the
// largest departures of T + V from its start and of y from Y0; `each` sees every sample and the
// angle th from the bottom.
struct BowlSwing {
  mech::SimulationStatus status = mech::SimulationStatus::success;
  std::vector<double> ups;
  double err_E = 0, err_y = 0;
};
BowlSwing swing_in_bowl(const ModelDescription& desc, double th0, double t_end, double dt,
                        const std::function<void(const mech::Sample&, double)>& each) {
  const double m = kBowlM, r = kBowlBallR, g = kBowlG, L = kBowlL;
  const Vector3d& S = kBowlS;
  const auto model = desc.instantiate({});
  Eigen::VectorXd q0(7), qd0 = Eigen::VectorXd::Zero(7);
  q0 << S + L * Vector3d(std::sin(th0), 0, -std::cos(th0)), 1, 0, 0, 0;
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.kernel = Kernel::cpp;
  o.active_constraints = all_names(*model);
  auto energy = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    const Vector3d wb = 2 * E_of(q.segment<4>(3)) * qd.segment<4>(3);
    return 0.5 * m * qd.head<3>().squaredNorm() + 0.5 * 0.4 * m * r * r * wb.squaredNorm() + m * g * (q[2] - S[2]);
  };
  const double E0 = energy(q0, qd0);
  BowlSwing out;
  double prev_x = q0[0] - S[0], prev_t = 0;
  int next = 1;
  out.status = mech::simulate(*model, q0, qd0, o, [&](const mech::StepView& v) {
    while (next * dt <= v.t + 1e-12) {
      const mech::Sample smp = v.sample(next * dt);
      const double x = smp.q[0] - S[0];
      if (prev_x < 0 && x >= 0) out.ups.push_back(prev_t + (smp.t - prev_t) * (-prev_x) / (x - prev_x));
      prev_x = x;
      prev_t = smp.t;
      out.err_E = std::max(out.err_E, std::abs(energy(smp.q, smp.qd) - E0));
      out.err_y = std::max(out.err_y, std::abs(smp.q[1] - S[1]));
      each(smp, std::atan2(x, -(smp.q[2] - S[2])));
      ++next;
    }
    return true;
  }).status;
  return out;
}
}  // namespace

// A homogeneous ball (J = 2/5 m r^2) rolling without slip in a spherical bowl
// (models/ball_bowl_bodies.toml: m = 0.5 kg, r = 0.1 m, bowl radius Rb = 1 m centred at
// (300, -200, 80) m, marker1's z up: the bottom is in the tangents' first chart, w1·n = 1).
// In the vertical plane y = Y0, with th the angle of the centre from the bottom and L = Rb - r,
// the centre moves at L th_d and no slip spins the ball at L th_d / r, so
// T = 1/2 (m + J/r^2) L^2 th_d^2 = 7/10 m L^2 th_d^2, V = -m g L cos(th):  7/5 L th_dd = -g sin(th),
// the pendulum of length 7/5 L: small oscillations at w^2 = 5 g / (7 L), and from th0 at rest the
// period is 2 pi/w (1 + th0^2/16 + O(th0^4)). Released from th0 = 1e-3 rad at rest, the mean period
// over 4 swings (upward zero crossings of x - X0, interpolated linearly between 1e-3 s samples: an
// error of (w dt)^2 dt/6 = 1.3e-9 s each, 6e-10 of the period) matches 2 pi/w to th0^2/8 = 1.25e-7
// relative (twice the th0^2/16 term; the integration at rtol 1e-11 adds ~1e-9); the energy
// T + V (from the state, V relative to the bowl's centre) stays at its initial value to 1e-5 of the
// swing's kinetic energy m g L (1 - cos th0) = 2.2e-6 J (positions carry atol 1e-13 m, m g 1e-13 =
// 5e-13 J = 2e-7 of it); the ball stays in the plane y = Y0 (1e-12 m) and the normal force is
// m g cos(th) + m |v|^2 / L (the centre's centripetal balance; th and v from the state) to 1e-9
// of m g. Beyond the bound, the period's excess over 2 pi/w is the th0^2/16 term itself to 1e-9
// (the th0^4 term is 4e-15; the crossings' interpolation ~6e-10 at most).
// Measured (Release): period excess 6.2539e-8 (th0^2/16 = 6.25e-8), energy 2.4e-7 of the swing's.
BOOST_AUTO_TEST_CASE(ball_rolling_in_a_spherical_bowl_oscillates_at_the_rolling_pendulums_frequency) {
  const double m = kBowlM, g = kBowlG, L = kBowlL, th0 = 1e-3;
  const double w = std::sqrt(5 * g / (7 * L)), T0 = 2 * M_PI / w, KE = m * g * L * (1 - std::cos(th0));
  const auto desc = load_model_file(model_path("ball_bowl_bodies.toml"));
  const int iN = output_index(*desc, "normal");
  double err_N = 0;
  const BowlSwing sw = swing_in_bowl(*desc, th0, 4.2 * T0, 1e-3, [&](const mech::Sample& smp, double th) {
    err_N = std::max(err_N, std::abs(smp.derived[iN] - (m * g * std::cos(th) + m * smp.qd.head<3>().squaredNorm() / L)));
  });
  BOOST_REQUIRE(sw.status == mech::SimulationStatus::success);
  BOOST_REQUIRE(sw.ups.size() >= 4);
  const double period = (sw.ups.back() - sw.ups.front()) / static_cast<double>(sw.ups.size() - 1);
  BOOST_TEST_MESSAGE("ball in a bowl: period " << period << " s vs 2 pi/w = " << T0 << " s, relative "
                     << period / T0 - 1 << " (th0^2/16 = " << th0 * th0 / 16 << "); |E - E0| " << sw.err_E / KE
                     << " of the swing's energy; |y - Y0| " << sw.err_y << " m; |N - (m g cos th + m v^2/L)| " << err_N / (m * g) << " of m g");
  BOOST_TEST(std::abs(period / T0 - 1) < th0 * th0 / 8);
  BOOST_TEST(std::abs(period / T0 - 1 - th0 * th0 / 16) < 1e-9);
  BOOST_TEST(sw.err_E < 1e-5 * KE);
  BOOST_TEST(sw.err_y < 1e-12);
  BOOST_TEST(err_N < 1e-9 * m * g);
}

// The same ball swinging far in the bowl, through both tangent charts (bodies_spatial.cpp,
// sphere_rows): released at rest at th0 = 2.3 rad (132°) from the bottom (the rows are bilateral,
// so the ball stays on the sphere above the rim), it crosses the circle w1·n = −1/2 where the rows
// change chart, once with marker1's z up (the bottom, w1·n = 1, in the first chart; the switch
// 60° from the top) and once with marker1 upside down (axis x, angle pi: then the bottom is
// n = −w1, the point where the first chart alone divided by zero, served by the second chart;
// the switch 60° from the bottom). Without slip the centre is the pendulum of length 7/5 L
// (above): its period from rest at th0 is exact, T = 4 sqrt(7 L/(5 g)) K(sin(th0/2))
// (std::comp_ellint_1), matched by the mean period of the upward zero crossings of x − X0
// (interpolated linearly between 1e-4 s samples; the interpolation's error is the same at every
// crossing and cancels) to 1e-8 relative; the energy stays E0 to 1e-8 of m g L (rtol 1e-11 over
// 3.3 swings); the ball stays in the plane y = Y0 (1e-10 m); the friction force's magnitude
// |(λ_x, λ_y)|, whichever pair carries it, is (2/7) m g |sin th| (from m L th_dd = −m g sin th + F_t
// with 7/5 L th_dd = −g sin th) to 1e-8 of m g.
// Measured (Release), both frames: period −4.5e-10 relative, energy 3.6e-9 of m g L, F_t 1.6e-9
// of m g, 13 chart switches; upside down the samples come within 1 + w1·n = 4e-10 of the first
// chart's singular point.
BOOST_AUTO_TEST_CASE(ball_swinging_in_a_bowl_through_both_tangent_charts_keeps_the_exact_pendulum_period) {
  const double m = kBowlM, g = kBowlG, L = kBowlL, th0 = 2.3;
  const double T = 4 * std::sqrt(7 * L / (5 * g)) * std::comp_ellint_1(std::sin(th0 / 2));
  std::ifstream in(model_path("ball_bowl_bodies.toml"));
  std::stringstream buf;
  buf << in.rdbuf();
  for (const bool flipped : {false, true}) {
    BOOST_TEST_CONTEXT((flipped ? "marker1 upside down" : "marker1 upright")) {
      std::string text = buf.str();
      if (flipped) {
        const std::string plain = "centre = [\"X0\", \"Y0\", \"Z0\"]";
        BOOST_REQUIRE(text.find(plain) != std::string::npos);
        text.replace(text.find(plain), plain.size(),
                     "centre = { at = [\"X0\", \"Y0\", \"Z0\"], axis = [1, 0, 0], angle = \"pi\" }");
      }
      text.replace(text.find("[model.outputs]"), 15, "[model.outputs]\nft = \"sqrt(lambda_roll_x^2 + lambda_roll_y^2)\"\ncw = \"roll_cw\"");
      const auto desc = load_model_text(text, "ball_bowl_swing.toml");
      const int iF = output_index(*desc, "ft"), iC = output_index(*desc, "cw");
      double err_F = 0, nearest = 2, prev_c = 0;
      int switches = 0;
      bool first = true;
      const BowlSwing sw = swing_in_bowl(*desc, th0, 3.3 * T, 1e-4, [&](const mech::Sample& smp, double th) {
        err_F = std::max(err_F, std::abs(smp.derived[iF] - 2.0 / 7.0 * m * g * std::abs(std::sin(th))));
        const double c = smp.derived[iC];  // w1·n: the first chart's singular point is c = -1
        nearest = std::min(nearest, 1 + c);
        if (!first && (c < -0.5) != (prev_c < -0.5)) ++switches;
        prev_c = c;
        first = false;
      });
      BOOST_REQUIRE(sw.status == mech::SimulationStatus::success);
      BOOST_REQUIRE(sw.ups.size() >= 3);
      const double period = (sw.ups.back() - sw.ups.front()) / static_cast<double>(sw.ups.size() - 1);
      BOOST_TEST_MESSAGE((flipped ? "upside down" : "upright") << ": period " << period << " s vs the exact " << T
                         << " s, relative " << period / T - 1 << "; |E - E0| " << sw.err_E / (m * g * L) << " of m g L; |y - Y0| "
                         << sw.err_y << " m; |F_t - 2/7 m g |sin th|| " << err_F / (m * g) << " of m g; " << switches
                         << " chart switches; closest 1 + w1.n " << nearest);
      BOOST_TEST(std::abs(period / T - 1) < 1e-8);
      BOOST_TEST(sw.err_E < 1e-8 * m * g * L);
      BOOST_TEST(sw.err_y < 1e-10);
      BOOST_TEST(err_F < 1e-8 * m * g);
      BOOST_TEST(switches >= 12);
      if (flipped) BOOST_TEST(nearest < 1e-6);  // through the first chart's singular point
    }
  }
}
