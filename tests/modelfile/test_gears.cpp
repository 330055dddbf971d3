// Gears and couplers (docs/bodies.md "Joints", docs/bodies-spatial.md "Gears and couplers")
// against solutions that do not use them: each machine is also solved in its one or two
// minimal coordinates, in closed form or by RK4 written here.
// - A bevel gear pair in space (models/bevel_gear_bodies.toml: two shafts in Euler parameters
//   on revolute joints written as rows, axes at right angles, 500 m from the origin; the gear's
//   row in velocity form) driven by a constant torque: omega_A = alpha t with
//   alpha = tau / (JA + n^2 JB), omega_B = n omega_A, the mesh torque on B n JB alpha, each
//   shaft's angle (read from its Euler parameters) alpha t^2 / 2 (n times it), the bearings'
//   forces the shafts' weights. Through several turns of each shaft.
// - The same pair with the shafts placed by revolute tree joints (a holonomic gear row,
//   fixed at the initial state) gives the same closed form.
// - A rack and pinion in the plane (a prismatic and a revolute joint written as rows: the gear
//   row is holonomic, travel + r angle fixed) on a slope under gravity:
//   (m + J / r^2) s_dd = -m g sin(beta), the mesh force on the rack m s_dd + m g sin(beta).
// - An open differential (models/differential_bodies.toml: a three-member `coupler`, Willis'
//   2 omega_c = omega_L + omega_R) against its minimal coordinates (omega_L, omega_R) by RK4,
//   with the coupler's torque on each shaft.
// - A rotational damper on a spatial revolute joint written as rows damps about its axis, and a
//   drive on one needs the inverse-dynamics torque J f'' + c f'.
// - Bad gears and couplers are input errors naming the key.
#define BOOST_TEST_MODULE modelfile_gears
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

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

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  BOOST_REQUIRE_MESSAGE(at != std::string::npos, "no '" << from << "' in the model text");
  return s.replace(at, from.size(), to);
}

// Runs the model and calls `check` at t = 0, dt, 2 dt, ..., t_end (dense output).
void run_on_grid(const mech::Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                 const std::vector<std::string>& active, double t_end, double dt, double tol,
                 const std::function<void(const mech::Sample&)>& check) {
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = tol;
  o.atol = tol * 1e-2;
  o.kernel = Kernel::cpp;
  o.active_constraints = active;
  int next = 0;
  const int n = static_cast<int>(std::lround(t_end / dt));
  const auto r = mech::simulate(model, q, qd, o, [&](const mech::StepView& v) {
    while (next <= n && next * dt <= v.t + 1e-12) {
      check(v.sample(std::max(v.t_prev, next * dt)));
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_REQUIRE(next == n + 1);
}

// Rotation matrix of Euler parameters e.
Matrix3d A_of(const Vector4d& e) {
  return Eigen::Quaterniond(e[0], e[1], e[2], e[3]).toRotationMatrix();
}
// The angle in (-pi, pi] of x reduced modulo 2 pi.
double wrap(double x) { return std::remainder(x, 2 * M_PI); }

// The bevel pair's data (models/bevel_gear_bodies.toml's defaults, written again).
const double JA = 0.02, JB = 0.05, n_ratio = -2.5, tau = 1.5, mA = 2.0, mB = 3.0, grav = 9.81;
const Vector3d P0(500.0, -300.0, 100.0);
const double alpha = tau / (JA + n_ratio * n_ratio * JB);
// Each shaft's axis is its body z; the bearings turn ground z onto x (A) and y (B).
const Matrix3d A0A = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
const Matrix3d A0B = Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitX()).toRotationMatrix();

}  // namespace

// Two shafts in Euler parameters on revolute rows, the gear in velocity form: against the
// closed form through 2.3 turns of A and 5.7 of B (4 s). The rates and the mesh torque to 1e-7
// relative (rtol 1e-10); the angles, read from the Euler parameters, to 1e-6 rad: the velocity
// form does not drift beyond the integration error; the bearings carry the weights (1e-9 N).
BOOST_AUTO_TEST_CASE(bevel_gear_on_spatial_revolute_rows_follows_the_reduced_inertia) {
  const auto desc = load_model_file(model_path("bevel_gear_bodies.toml"));
  const int mesh = desc->constraint_index("mesh");
  BOOST_REQUIRE(mesh >= 0);
  BOOST_TEST((desc->constraints()[static_cast<std::size_t>(mesh)].kind == mech::ConstraintKind::velocity));
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = Eigen::VectorXd::Zero(model->n());
  const int xA = name_index(names, "shaftA_x"), eA = name_index(names, "shaftA_e0");
  const int xB = name_index(names, "shaftB_x"), eB = name_index(names, "shaftB_e0");
  const Eigen::Quaterniond qA(A0A), qB(A0B);
  q.segment<3>(xA) = P0;
  q.segment<4>(eA) << qA.w(), qA.x(), qA.y(), qA.z();
  q.segment<3>(xB) = P0 + Vector3d(0.3, 0.2, 0);
  q.segment<4>(eB) << qB.w(), qB.x(), qB.y(), qB.z();
  const int iwA = output_index(*desc, "wA"), iwB = output_index(*desc, "wB");
  const int iM = output_index(*desc, "M_mesh_z"), iFB = output_index(*desc, "F_bearB_x");
  const int iMB = output_index(*desc, "M_bearB_x"), iFA = output_index(*desc, "F_bearA_x");
  double err_w = 0, err_M = 0, err_th = 0, err_F = 0, max_MB = 0;
  run_on_grid(*model, q, qd, desc->default_active_constraints(), 4.0, 0.25, 1e-10, [&](const mech::Sample& s) {
    const double t = s.t, wA = alpha * t, thA = 0.5 * alpha * t * t;
    err_w = std::max({err_w, std::abs(s.derived[iwA] - wA), std::abs(s.derived[iwB] - n_ratio * wA)});
    err_M = std::max(err_M, std::abs(s.derived[iM] - n_ratio * JB * alpha));
    // The shafts' angles about their axes: A(t) A0ᵀ = rotation by th about the bearing's axis.
    const Matrix3d RA = A_of(s.q.segment<4>(eA)) * A0A.transpose();
    const Matrix3d RB = A_of(s.q.segment<4>(eB)) * A0B.transpose();
    const double th_A = std::atan2(RA(2, 1), RA(1, 1));   // about x
    const double th_B = std::atan2(RB(0, 2), RB(2, 2));   // about y
    err_th = std::max({err_th, std::abs(wrap(th_A - thA)), std::abs(wrap(th_B - n_ratio * thA))});
    // Joint frames: A's x is ground -z, B's y is ground -z; each bearing holds its shaft's weight.
    const Vector3d FA(-mA * grav, 0, 0), FB(0, -mB * grav, 0);
    err_F = std::max({err_F, (s.derived.segment<3>(iFA) - FA).cwiseAbs().maxCoeff(),
                      (s.derived.segment<3>(iFB) - FB).cwiseAbs().maxCoeff()});
    max_MB = std::max(max_MB, s.derived.segment<3>(iMB).cwiseAbs().maxCoeff());
  });
  BOOST_TEST_MESSAGE("bevel gear (rows, velocity form): |w - closed form| " << err_w << " rad/s, |M_mesh_z - n JB alpha| "
                     << err_M << " N m, angles " << err_th << " rad, bearing forces " << err_F << " N, bearing B's moment " << max_MB);
  BOOST_TEST(err_w < 1e-7 * alpha * 4.0 * std::abs(n_ratio));
  BOOST_TEST(err_M < 1e-7 * std::abs(n_ratio * JB * alpha));
  BOOST_TEST(err_th < 1e-6);
  BOOST_TEST(err_F < 1e-9);
  BOOST_TEST(max_MB < 1e-9);
}

// The same pair placed by revolute tree joints (coordinates thA, thB; no Euler parameters): the
// gear's row is holonomic, thB - n thA fixed at the initial state (nonzero here: 0.4 rad), and
// the closed form holds as before.
BOOST_AUTO_TEST_CASE(gear_between_tree_joints_is_holonomic_and_gives_the_same_closed_form) {
  std::string text = model_text("bevel_gear_bodies.toml");
  text = replace(text, "body2 = \"shaftA\"\n", "body2 = \"shaftA\"\ncoordinates = [\"thA\"]\n");
  text = replace(text, "body2 = \"shaftB\"\n", "body2 = \"shaftB\"\ncoordinates = [\"thB\"]\n");
  const auto desc = load_model_text(text, "bevel_gear_tree.toml");
  BOOST_REQUIRE(desc->coordinates().size() == 2u);
  const auto& c = desc->constraints()[static_cast<std::size_t>(desc->constraint_index("mesh"))];
  BOOST_TEST((c.kind == mech::ConstraintKind::holonomic));
  BOOST_TEST(c.from_initial);
  Eigen::VectorXd q(2), qd = Eigen::VectorXd::Zero(2);
  q << 0.3, 0.3 * n_ratio + 0.4;
  const auto model = desc->instantiate({}, q);
  const int ith = name_index(desc->coordinates(), "thB");
  const int iM = output_index(*desc, "M_mesh_z"), iwB = output_index(*desc, "wB");
  double err_w = 0, err_M = 0, err_th = 0;
  run_on_grid(*model, q, qd, desc->default_active_constraints(), 4.0, 0.25, 1e-10, [&](const mech::Sample& s) {
    const double t = s.t;
    err_w = std::max(err_w, std::abs(s.derived[iwB] - n_ratio * alpha * t));
    err_M = std::max(err_M, std::abs(s.derived[iM] - n_ratio * JB * alpha));
    err_th = std::max(err_th, std::abs(s.q[ith] - (0.3 * n_ratio + 0.4 + n_ratio * 0.5 * alpha * t * t)));
  });
  BOOST_TEST_MESSAGE("bevel gear (tree joints, holonomic): |wB - closed form| " << err_w << ", |M - n JB alpha| " << err_M
                     << ", |thB - closed form| " << err_th);
  BOOST_TEST(err_w < 1e-8);
  BOOST_TEST(err_M < 1e-9);
  BOOST_TEST(err_th < 1e-8);
}

namespace {

// A rack on a slope (x down-slope at angle beta: the slide's x axis points along
// (cos beta, sin beta)) meshing with a pinion on a fixed hub: travel s = -r (angle).
const char* kRackPinion = R"(
[model]
name = "rack_pinion"
[model.parameters]
m = 4.0
J = 0.03
r = 0.06
beta = -0.5
g = 9.81
X0 = 1200.0
Y0 = -800.0
[model.body.ground.markers]
slope = { at = ["X0", "Y0"], angle = "beta" }
hub = { at = ["X0 + 0.3", "Y0 + 0.4"] }
[model.body.rack]
mass = "m"
inertia = 0.5
[model.body.pinion]
mass = 1.0
inertia = "J"
[model.joint.slide]
type = "prismatic"
marker1 = "slope"
body2 = "rack"
[model.joint.pin]
type = "revolute"
marker1 = "hub"
body2 = "pinion"
[model.joint.mesh]
type = "gear"
joint1 = "pin"
joint2 = "slide"
ratio = "-r"
[model.force.gravity]
type = "gravity"
g = [0, "-g"]
)";

}  // namespace

// Planar rows: the travel (d . x of the slide) and the relative angle are functions of q, so
// the gear's row is holonomic. (m + J/r^2) s_dd = -m g sin(beta) (beta < 0: the rack runs down
// the slope's x); the mesh's force on the rack, along the slide's x, is m s_dd + m g sin(beta).
BOOST_AUTO_TEST_CASE(rack_and_pinion_on_planar_rows_is_a_holonomic_gear) {
  const auto desc = load_model_text(kRackPinion, "rack_pinion.toml");
  const auto& c = desc->constraints()[static_cast<std::size_t>(desc->constraint_index("mesh"))];
  BOOST_TEST((c.kind == mech::ConstraintKind::holonomic));
  const auto& names = desc->coordinates();
  const double m = 4.0, J = 0.03, r = 0.06, beta = -0.5, g = 9.81;
  const Eigen::Vector2d X0(1200.0, -800.0), ex(std::cos(beta), std::sin(beta));
  Eigen::VectorXd q = Eigen::VectorXd::Zero(desc->coordinates().size()), qd = q;
  const double s0 = 0.1, phi0 = 0.7;  // travel and angle at t = 0
  q[name_index(names, "rack_x")] = X0[0] + s0 * ex[0];
  q[name_index(names, "rack_y")] = X0[1] + s0 * ex[1];
  q[name_index(names, "rack_th")] = beta;
  q[name_index(names, "pinion_x")] = X0[0] + 0.3;
  q[name_index(names, "pinion_y")] = X0[1] + 0.4;
  q[name_index(names, "pinion_th")] = phi0;
  const auto model = desc->instantiate({}, q);
  const double sdd = -m * g * std::sin(beta) / (m + J / (r * r));
  const int iF = output_index(*desc, "F_mesh_x");
  const int ix = name_index(names, "rack_x"), ith = name_index(names, "pinion_th");
  double err_s = 0, err_phi = 0, err_F = 0;
  run_on_grid(*model, q, qd, desc->default_active_constraints(), 1.0, 0.05, 1e-10, [&](const mech::Sample& smp) {
    const double t = smp.t, s = s0 + 0.5 * sdd * t * t;
    err_s = std::max(err_s, std::abs((smp.q[ix] - X0[0]) / ex[0] - s));
    err_phi = std::max(err_phi, std::abs(smp.q[ith] - (phi0 - (s - s0) / r)));
    err_F = std::max(err_F, std::abs(smp.derived[iF] - (m * sdd + m * g * std::sin(beta))));
  });
  BOOST_TEST_MESSAGE("rack and pinion: |s - closed form| " << err_s << " m, |phi - closed form| " << err_phi
                     << " rad, |F_mesh_x - m (s_dd + g sin beta)| " << err_F << " N (of " << m * g * std::sin(-beta) << ")");
  BOOST_TEST(err_s < 1e-8);
  BOOST_TEST(err_phi < 1e-7);
  BOOST_TEST(err_F < 1e-7);
}

// The open differential (models/differential_bodies.toml) against its minimal coordinates
// (wL, wR), wc = (wL + wR)/2: M w_d = (tau/2 - cL wL, tau/2 - cR wR),
// M = diag(JL, JR) + Jc/4 [1 1; 1 1], by RK4 at h = 1e-4 s (a linear system with time
// constants above 0.3 s: RK4's error ~1e-15). The coupler's torques: on the carrier
// Jc wc_d - tau, on each half-shaft J wi_d + ci wi (equal: an open differential splits the
// torque evenly). 3 s, from rest.
BOOST_AUTO_TEST_CASE(open_differential_coupler_follows_the_minimal_coordinate_model) {
  const auto desc = load_model_file(model_path("differential_bodies.toml"));
  BOOST_TEST((desc->constraints()[static_cast<std::size_t>(desc->constraint_index("spider"))].kind ==
              mech::ConstraintKind::velocity));
  const double Jc = 0.08, JL = 0.5, JR = 0.7, cL = 0.9, cR = 0.3, tq = 20.0;
  const Vector3d P(-250.0, 400.0, 0.35);
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
  const Eigen::Quaterniond e(A0A);  // body z along ground x
  const char* body[3] = {"carrier", "shaftL", "shaftR"};
  const double dx[3] = {0.0, -0.6, 0.6};
  for (int b = 0; b < 3; ++b) {
    q.segment<3>(name_index(names, std::string(body[b]) + "_x")) = P + Vector3d(dx[b], 0, 0);
    q.segment<4>(name_index(names, std::string(body[b]) + "_e0")) << e.w(), e.x(), e.y(), e.z();
  }
  const auto model = desc->instantiate({}, q);
  Eigen::Matrix2d M;
  M << JL + Jc / 4, Jc / 4, Jc / 4, JR + Jc / 4;
  const Eigen::Matrix2d Mi = M.inverse();
  auto f = [&](const Eigen::Vector2d& w) {
    return Eigen::Vector2d(Mi * Eigen::Vector2d(tq / 2 - cL * w[0], tq / 2 - cR * w[1]));
  };
  const double h = 1e-4, dt = 0.1;
  const int steps_per = static_cast<int>(std::lround(dt / h));
  Eigen::Vector2d w(0, 0);
  const int iwc = output_index(*desc, "wc"), iwL = output_index(*desc, "wL"), iwR = output_index(*desc, "wR");
  const int iMc = output_index(*desc, "M_spider_bear_c"), iML = output_index(*desc, "M_spider_bear_L"),
            iMR = output_index(*desc, "M_spider_bear_R");
  double err_w = 0, err_M = 0, w_max = 0;
  int k = 0;
  run_on_grid(*model, q, qd, desc->default_active_constraints(), 3.0, dt, 1e-10, [&](const mech::Sample& s) {
    if (k++ > 0)
      for (int i = 0; i < steps_per; ++i) {
        const Eigen::Vector2d k1 = f(w), k2 = f(w + h / 2 * k1), k3 = f(w + h / 2 * k2), k4 = f(w + h * k3);
        w += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
    const Eigen::Vector2d wd = f(w);
    w_max = std::max(w_max, w.cwiseAbs().maxCoeff());
    err_w = std::max({err_w, std::abs(s.derived[iwL] - w[0]), std::abs(s.derived[iwR] - w[1]),
                      std::abs(s.derived[iwc] - 0.5 * (w[0] + w[1]))});
    err_M = std::max({err_M, std::abs(s.derived[iMc] - (Jc * 0.5 * (wd[0] + wd[1]) - tq)),
                      std::abs(s.derived[iML] - (JL * wd[0] + cL * w[0])),
                      std::abs(s.derived[iMR] - (JR * wd[1] + cR * w[1]))});
  });
  BOOST_TEST_MESSAGE("open differential: |w - minimal model| " << err_w << " rad/s (of " << w_max
                     << "), |coupler torques - minimal model| " << err_M << " N m");
  BOOST_TEST(w_max > 20.0);  // it turns: the right wheel, lighter loaded, runs ahead
  BOOST_TEST(err_w < 1e-7 * w_max);
  BOOST_TEST(err_M < 1e-7 * tq);
}

// A rotational damper on a spatial revolute joint written as rows (the same rate the gears
// use) damps about the joint's axis: w = w0 exp(-c t / J). Before round 41 it damped the
// ground-z component of the relative rate (for this axis, ground x: nothing; w stayed w0, exit 0).
BOOST_AUTO_TEST_CASE(rotational_damper_on_spatial_revolute_rows_damps_about_the_joint_axis) {
  const std::string text = R"(
[model]
name = "spin"
[model.body.ground.markers]
bearing = { at = [300, -200, 50], axis = [0, 1, 0], angle = "pi/2" }
[model.body.shaft]
kind = "spatial"
mass = 12.0
inertia = [0.9, 0.8, 0.5]
[model.joint.bear]
type = "revolute"
marker1 = "bearing"
body2 = "shaft"
[model.force.load]
type = "rotational_spring_damper"
joint = "bear"
damping = 0.4
[model.outputs]
w = "shaft_w3"
)";
  const auto desc = load_model_text(text, "spin.toml");
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
  const Eigen::Quaterniond e(A0A);  // body z along ground x
  const double w0 = 10.0, c = 0.4, J = 0.5;
  q.segment<3>(name_index(names, "shaft_x")) = Vector3d(300, -200, 50);
  q.segment<4>(name_index(names, "shaft_e0")) << e.w(), e.x(), e.y(), e.z();
  // e_d = 1/2 e (x) (0, w body): body z
  const Eigen::Quaterniond ed = e * Eigen::Quaterniond(0, 0, 0, 0.5 * w0);
  qd.segment<4>(name_index(names, "shaft_e0")) << ed.w(), ed.x(), ed.y(), ed.z();
  const auto model = desc->instantiate({});
  const int iw = output_index(*desc, "w");
  double err = 0;
  run_on_grid(*model, q, qd, desc->default_active_constraints(), 2.0, 0.1, 1e-10, [&](const mech::Sample& s) {
    err = std::max(err, std::abs(s.derived[iw] - w0 * std::exp(-c * s.t / J)));
  });
  BOOST_TEST_MESSAGE("damper on a spatial revolute written as rows: |w - w0 exp(-c t/J)| " << err << " rad/s");
  BOOST_TEST(err < 1e-8 * w0);
}

// A drive on a spatial revolute joint written as rows (velocity form: the rate follows f'(t))
// is inverse dynamics: the shaft (J = 0.5 about its axis, a damper c = 0.4) turned by
// f(t) = a sin(w t) + b t needs the torque J f'' + c f' (M_motor_z, about the joint's axis in
// its frame); its angle, read from the Euler parameters, is f(t). 3 s, two turns.
BOOST_AUTO_TEST_CASE(drive_on_spatial_revolute_rows_gives_the_inverse_dynamics_torque) {
  const std::string text = R"(
[model]
name = "driven_spin"
[model.parameters]
a = 0.8
w = 5.0
b = 3.0
[model.body.ground.markers]
bearing = { at = [300, -200, 50], axis = [0, 1, 0], angle = "pi/2" }
[model.body.shaft]
kind = "spatial"
mass = 12.0
inertia = [0.9, 0.8, 0.5]
[model.joint.bear]
type = "revolute"
marker1 = "bearing"
body2 = "shaft"
[model.joint.motor]
type = "drive"
joint = "bear"
motion = "a*sin(w*t) + b*t"
[model.force.load]
type = "rotational_spring_damper"
joint = "bear"
damping = 0.4
)";
  const auto desc = load_model_text(text, "driven_spin.toml");
  BOOST_TEST((desc->constraints()[static_cast<std::size_t>(desc->constraint_index("motor"))].kind ==
              mech::ConstraintKind::velocity));
  const auto& names = desc->coordinates();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<int>(names.size())), qd = q;
  const Eigen::Quaterniond e(A0A);
  const double a = 0.8, w = 5.0, b = 3.0, c = 0.4, J = 0.5;
  const int ie = name_index(names, "shaft_e0");
  q.segment<3>(name_index(names, "shaft_x")) = Vector3d(300, -200, 50);
  q.segment<4>(ie) << e.w(), e.x(), e.y(), e.z();
  const Eigen::Quaterniond ed = e * Eigen::Quaterniond(0, 0, 0, 0.5 * (a * w + b));  // f'(0)
  qd.segment<4>(ie) << ed.w(), ed.x(), ed.y(), ed.z();
  const auto model = desc->instantiate({});
  const int iM = output_index(*desc, "M_motor_z");
  double err_M = 0, err_th = 0, M_max = 0;
  run_on_grid(*model, q, qd, desc->default_active_constraints(), 3.0, 0.05, 1e-10, [&](const mech::Sample& s) {
    const double t = s.t, f = a * std::sin(w * t) + b * t, fd = a * w * std::cos(w * t) + b,
                 fdd = -a * w * w * std::sin(w * t);
    M_max = std::max(M_max, std::abs(J * fdd + c * fd));
    err_M = std::max(err_M, std::abs(s.derived[iM] - (J * fdd + c * fd)));
    const Matrix3d R = A_of(s.q.segment<4>(ie)) * A0A.transpose();
    err_th = std::max(err_th, std::abs(wrap(std::atan2(R(2, 1), R(1, 1)) - f)));
  });
  BOOST_TEST_MESSAGE("drive on a spatial revolute written as rows: |M - (J f'' + c f')| " << err_M << " N m (of "
                     << M_max << "), |angle - f| " << err_th << " rad");
  BOOST_TEST(err_M < 1e-7 * M_max);
  BOOST_TEST(err_th < 1e-7);
}

// Gears and couplers that name the wrong things are input errors naming the key.
BOOST_AUTO_TEST_CASE(bad_gears_and_couplers_are_rejected_naming_the_key) {
  const std::string bevel = model_text("bevel_gear_bodies.toml");
  const std::string diff = model_text("differential_bodies.toml");
  struct Case {
    std::string text;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      // a spherical joint has no single motion to gear
      {replace(replace(bevel, "type = \"revolute\"\nbody1 = \"ground\"\nmarker1 = \"bearingB\"",
                       "type = \"spherical\"\nbody1 = \"ground\"\nmarker1 = \"bearingB\""),
               "ratio = \"n\"", "ratio = \"n\""),
       {"model.joint.mesh.joint2", "revolute, prismatic or cylindrical", "'bearB' (spherical)"}},
      {replace(bevel, "joint2 = \"bearB\"", "joint2 = \"nowhere\""), {"model.joint.mesh.joint2", "nowhere", "bearA"}},
      {replace(bevel, "joint2 = \"bearB\"", "joint2 = \"bearA\""), {"model.joint.mesh.joint2", "other than joint1"}},
      {replace(bevel, "joint2 = \"bearB\"", "joint2 = \"bearA\"\ndof2 = \"rotation\""), {"model.joint.mesh.joint2", "other than joint1"}},
      {replace(bevel, "joint2 = \"bearB\"", "joint2 = \"mesh\""), {"model.joint.mesh.joint2", "(gear)"}},
      {replace(bevel, "ratio = \"n\"\n", ""), {"model.joint.mesh.ratio"}},
      {replace(bevel, "joint1 = \"bearA\"", "joint1 = \"bearA\"\ndof1 = \"translation\""),
       {"model.joint.mesh.dof1", "\"rotation\"", "revolute joint 'bearA'", "got 'translation'"}},
      // a cylindrical joint: which of its two motions
      {replace(bevel, "type = \"revolute\"\nbody1 = \"ground\"\nmarker1 = \"bearingB\"",
               "type = \"cylindrical\"\nbody1 = \"ground\"\nmarker1 = \"bearingB\""),
       {"model.joint.mesh.dof2", "\"rotation\" or \"translation\"", "cylindrical joint 'bearB'"}},
      {replace(diff, "ratios = [2, -1, -1]", "ratios = [2, -1]"), {"model.joint.spider.ratios", "a list of 3"}},
      {replace(diff, "type = \"coupler\"\njoints = [\"bear_c\", \"bear_L\", \"bear_R\"]\nratios = [2, -1, -1]",
               "type = \"drive\"\njoint = \"spider\"\nmotion = \"t\""),
       {"model.joint.spider.joint", "'spider' (drive)"}},
      {replace(diff, "joints = [\"bear_c\", \"bear_L\", \"bear_R\"]", "joints = [\"bear_c\"]"),
       {"model.joint.spider.joints", "two or more"}},
      {replace(diff, "joints = [\"bear_c\", \"bear_L\", \"bear_R\"]", "joints = [\"bear_c\", \"bear_L\", \"bear_c\"]"),
       {"model.joint.spider.joints[2]", "each motion once"}},
      {replace(diff, "ratios = [2, -1, -1]", "ratios = [2, -1, -1]\ndofs = [\"\", \"\"]"), {"model.joint.spider.dofs"}},
      // the angle of a spatial revolute joint written as rows is not a function of q
      {replace(diff, "damping = \"cL\"", "damping = \"cL\"\nstiffness = 100.0"),
       {"model.force.loadL.stiffness", "not a function of the coordinates", "bushing"}},
  };
  for (const auto& c : cases) {
    const std::string msg = input_error_of([&] { load_model_text(c.text, "gear_bad.toml"); });
    BOOST_TEST_INFO("message: " << msg);
    BOOST_TEST(contains_all(msg, {"gear_bad.toml"}));
    for (const auto& p : c.parts) {
      BOOST_TEST_INFO("message: " << msg);
      BOOST_TEST(msg.find(p) != std::string::npos, "expected '" << p << "'");
    }
  }
}
