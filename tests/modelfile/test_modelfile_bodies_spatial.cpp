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
// - a wheel on an accelerating deck rolls, relative to the deck, as on a fixed plane under the
//   gravity of the deck's frame (the wheel joint's moving-plane rows);
// - inertia tensors that are not symmetric or not positive definite are rejected naming the key;
// - the Whipple bicycle as bodies (models/whipple_bodies.toml) conserves energy in a nonlinear
//   run and, between its weave and capsize speeds, rights itself after a push in roll, while
//   below the weave speed it does not.
#define BOOST_TEST_MODULE modelfile_bodies_spatial
#include <boost/test/unit_test.hpp>
#include "common/eigen_instances.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "common/eigen_instances.hpp"

#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

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
int index_of_name(const std::vector<std::string>& names, const std::string& name) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  BOOST_FAIL("no coordinate " << name);
  return -1;
}
int output_index(const ModelDescription& d, const std::string& name) {
  for (std::size_t i = 0; i < d.outputs().size(); ++i)
    if (d.outputs()[i].name == name) return static_cast<int>(i);
  BOOST_FAIL("no output " << name);
  return -1;
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
    const int ic = index_of_name(names, "coin_x");
    q.segment<7>(ic) = c;
    qd.segment<7>(ic) = cd;
    if (deck) {
      q.segment<3>(index_of_name(names, "deck_x")) = P0;
      q[index_of_name(names, "deck_e0")] = 1.0;
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
