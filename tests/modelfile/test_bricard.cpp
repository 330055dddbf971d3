// IFToMM benchmark A04, Bricard's mechanism (models/bricard_a04.toml: five spatial rods, six
// revolute joints all active, 35 coordinates, 35 rows of rank 34) against an independent
// joint-angle model written here (issue 21's validation):
//   rod k turns relative to rod k-1 about a fixed axis by the joint angle th_k (rod 1 about
//   ground y), R_k = R_{k-1} Rot(a_k, th_k), o_{k+1} = o_k + R_k l_k;
//   the loop closes when rod 5's far end is at (0, 0, 1) and rod 5's x axis is ground's x
//   (the sixth joint): 6 equations (rank 4) in th_2..th_5 given th_1, solved by Gauss-Newton;
//   the tangent dth/dth_1 by least squares on the closure Jacobian (complex steps: exact to
//   rounding);
//   T = 1/2 m(th_1) th_1d^2 with m = sum_k (m |c_k'|^2 + w_k'^T J_k w_k') (c_k the centre of
//   mass, w_k' the body angular velocity per unit th_1d), V = g m sum_k y(c_k), and Lagrange's
//   equation m th_1dd + 1/2 m' th_1d^2 + V' = 0 integrated by RK4 (m' by central differences).
// Nothing here uses pcsim's bodies, joints, Euler parameters or rank-revealing solves.
#define BOOST_TEST_MODULE modelfile_bricard
#include <boost/test/unit_test.hpp>
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <fstream>
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
using cd = std::complex<double>;

namespace {

const double grav = 9.81, mass_rod = 1.0, Jt = (1.0 + 0.01) / 12.0, Ja = 0.02 / 12.0;
// Joint axes (in the frame of the rod before the joint; all frames are ground's at th = 0),
// rod vectors (origin to far end) and centres of mass, rod k = 1..5 at index k-1.
const int axis_of[5] = {1, 2, 0, 1, 2};  // y, z, x, y, z
const Vector3d rod_vec[5] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 1, 0}};
const int along[5] = {0, 1, 2, 0, 1};  // the rod's own axis (Ja about it)

template <class T>
using M3 = Eigen::Matrix<T, 3, 3>;
template <class T>
using V3 = Eigen::Matrix<T, 3, 1>;

template <class T>
M3<T> rot(int axis, T a) {
  M3<T> R = M3<T>::Identity();
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  R(i, i) = cos(a);
  R(i, j) = -sin(a);
  R(j, i) = sin(a);
  R(j, j) = cos(a);
  return R;
}

template <class T>
struct Chain {
  M3<T> R[5];
  V3<T> o[5], c[5], end;
};

template <class T>
Chain<T> chain(const Eigen::Matrix<T, 5, 1>& th) {
  Chain<T> C;
  M3<T> R = M3<T>::Identity();
  V3<T> o = V3<T>::Zero();
  for (int k = 0; k < 5; ++k) {
    R = (R * rot<T>(axis_of[k], th[k])).eval();
    C.R[k] = R;
    C.o[k] = o;
    C.c[k] = o + R * (rod_vec[k].cast<T>() * T(0.5));
    o = o + R * rod_vec[k].cast<T>();
  }
  C.end = o;
  return C;
}

// The closure residual: rod 5's far end at (0, 0, 1), its x axis along ground x.
template <class T>
Eigen::Matrix<T, 6, 1> closure(const Eigen::Matrix<T, 5, 1>& th) {
  const Chain<T> C = chain(th);
  Eigen::Matrix<T, 6, 1> F;
  F.template head<3>() = C.end - V3<T>(T(0), T(0), T(1));
  F.template tail<3>() = C.R[4].col(0) - V3<T>(T(1), T(0), T(0));
  return F;
}

using V5 = Eigen::Matrix<double, 5, 1>;
using J65 = Eigen::Matrix<double, 6, 5>;

J65 closure_jacobian(const V5& th) {
  J65 J;
  const double h = 1e-30;
  for (int i = 0; i < 5; ++i) {
    Eigen::Matrix<cd, 5, 1> z = th.cast<cd>();
    z[i] += cd(0, h);
    J.col(i) = closure(z).imag() / h;
  }
  return J;
}

// th_2..th_5 for th_1 (Gauss-Newton from the guess, to rounding).
V5 close_loop(double th1, V5 guess) {
  guess[0] = th1;
  for (int it = 0; it < 50; ++it) {
    const Eigen::Matrix<double, 6, 1> F = closure<double>(guess);
    const Eigen::Matrix<double, 6, 4> Jr = closure_jacobian(guess).rightCols<4>();
    const Eigen::Vector4d d = Jr.colPivHouseholderQr().solve(-F);
    guess.tail<4>() += d;
    if (d.norm() < 1e-15 && F.norm() < 1e-14) break;
  }
  BOOST_REQUIRE(closure<double>(guess).norm() < 1e-12);
  return guess;
}

// dth/dth_1 (the tangent of the configuration curve).
V5 tangent(const V5& th) {
  const J65 J = closure_jacobian(th);
  V5 t;
  t[0] = 1.0;
  t.tail<4>() = J.rightCols<4>().colPivHouseholderQr().solve(-J.col(0));
  return t;
}

struct Point {
  V5 th, t;          // angles, tangent
  Chain<double> C;   // the geometry
  Vector3d cd_[5];   // centre-of-mass velocities per unit th_1d
  Vector3d wb[5];    // body angular velocities per unit th_1d
  Vector3d w[5];     // ground angular velocities per unit th_1d
  double m = 0, V = 0, Vd = 0;
};

Point point(double th1, const V5& guess) {
  Point P;
  P.th = close_loop(th1, guess);
  P.t = tangent(P.th);
  P.C = chain<double>(P.th);
  const double h = 1e-30;
  Eigen::Matrix<cd, 5, 1> z = P.th.cast<cd>();
  z += P.t.cast<cd>() * cd(0, h);
  const Chain<cd> Cc = chain<cd>(z);
  for (int k = 0; k < 5; ++k) {
    P.cd_[k] = Cc.c[k].imag() / h;
    const Matrix3d Rd = Cc.R[k].imag() / h;
    const Matrix3d W = Rd * P.C.R[k].transpose();
    P.w[k] = Vector3d(0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1)));
    P.wb[k] = P.C.R[k].transpose() * P.w[k];
    Vector3d J(Jt, Jt, Jt);
    J[along[k]] = Ja;
    P.m += mass_rod * P.cd_[k].squaredNorm() + P.wb[k].dot(J.cwiseProduct(P.wb[k]));
    P.V += mass_rod * grav * P.C.c[k][1];
    P.Vd += mass_rod * grav * P.cd_[k][1];
  }
  return P;
}

double accel(double th1, double thd, V5& guess) {
  const double e = 1e-5;
  const Point P = point(th1, guess);
  guess = P.th;
  const double md = (point(th1 + e, guess).m - point(th1 - e, guess).m) / (2 * e);
  return -(0.5 * md * thd * thd + P.Vd) / P.m;
}

Vector4d e_of_matrix(const Matrix3d& A) {
  const Eigen::Quaterniond q(A);
  Vector4d e(q.w(), q.x(), q.y(), q.z());
  return e[0] < 0 ? Vector4d(-e) : e;
}
Eigen::Matrix<double, 3, 4> E_of(const Vector4d& e) {
  Eigen::Matrix<double, 3, 4> E;
  E << -e[1], e[0], -e[3], e[2], -e[2], e[3], e[0], -e[1], -e[3], -e[2], e[1], e[0];
  return E;
}

// pcsim's state (q, qd) at the oracle's point with rate thd.
void state_of(const Point& P, double thd, const std::vector<std::string>& names, Eigen::VectorXd& q,
              Eigen::VectorXd& qd) {
  q = Eigen::VectorXd::Zero(static_cast<int>(names.size()));
  qd = q;
  for (int k = 0; k < 5; ++k) {
    const std::string b = "rod" + std::to_string(k + 1) + "_";
    // the body frame's origin is the rod's first joint; its velocity from the centre's
    const Vector3d od = P.cd_[k] - P.w[k].cross(P.C.c[k] - P.C.o[k]);
    for (int i = 0; i < 3; ++i) {
      q[name_index(names, b + "xyz"[i])] = P.C.o[k][i];
      qd[name_index(names, b + "xyz"[i])] = od[i] * thd;
    }
    const Vector4d e = e_of_matrix(P.C.R[k]);
    const Vector4d ed = 0.5 * E_of(e).transpose() * (P.w[k] * thd);
    for (int i = 0; i < 4; ++i) {
      q[name_index(names, b + "e" + std::to_string(i))] = e[i];
      qd[name_index(names, b + "e" + std::to_string(i))] = ed[i];
    }
  }
}

}  // namespace

// Released from rest in the benchmark's position, pcsim (all six joints active, rtol 1e-8)
// must follow the oracle (RK4, h = 1e-3 s; its own energy drifts by ~1e-10 J) for 0.6 s (rod 1
// turns by 0.37 rad, the potential energy falls by 2.35 J; longer runs cost ~2.4 s of CPU per
// simulated second, see docs/redundant.md): every rod's origin to 1e-6 m and rotation matrix to
// 1e-6, and the total energy, computed from pcsim's state by the oracle's formulas, constant to
// 1e-6 of the potential energy's swing. The oracle's closure and tangent are exact to rounding
// and m' is a central difference (~1e-10), so the bounds are 100 rtol: the integrator's error
// with margin. Measured: origins 1.7e-8 m, rotations 8e-9, energy 1.5e-7 J (6.5e-8 of 2.35 J).
BOOST_AUTO_TEST_CASE(bricard_follows_the_independent_joint_angle_model_and_keeps_its_energy) {
  const auto desc = load_model_file(model_path("bricard_a04.toml"));
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  BOOST_REQUIRE(model->n() == 35);

  const double t_end = 0.6, grid = 1e-2;
  const int n_grid = static_cast<int>(std::lround(t_end / grid)), sub = 10;
  std::vector<std::pair<double, double>> oracle(n_grid + 1);
  V5 guess = V5::Zero();
  double th = 0.0, thd = 0.0;
  oracle[0] = {th, thd};
  const double h = grid / sub;
  for (int k = 1; k <= n_grid; ++k) {
    for (int j = 0; j < sub; ++j) {
      const double k1x = thd, k1v = accel(th, thd, guess);
      const double k2x = thd + 0.5 * h * k1v, k2v = accel(th + 0.5 * h * k1x, k2x, guess);
      const double k3x = thd + 0.5 * h * k2v, k3v = accel(th + 0.5 * h * k2x, k3x, guess);
      const double k4x = thd + h * k3v, k4v = accel(th + h * k3x, k4x, guess);
      th += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      thd += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    oracle[k] = {th, thd};
  }
  double th_min = 0, th_max = 0;
  for (const auto& [a, b] : oracle) th_min = std::min(th_min, a), th_max = std::max(th_max, a);
  const Point P0 = point(0.0, V5::Zero());
  const Point Pe = point(th, guess);
  const double E0 = P0.V, drift = std::abs(0.5 * Pe.m * thd * thd + Pe.V - E0);
  BOOST_TEST_MESSAGE("oracle: th_1 in [" << th_min << ", " << th_max << "] rad; energy drift " << drift
                                         << " J");
  BOOST_TEST(th_max - th_min > 0.3);  // it moves: the start is no equilibrium

  Eigen::VectorXd q, qd;
  state_of(P0, 0.0, names, q, qd);
  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = desc->default_active_constraints();
  BOOST_REQUIRE(o.active_constraints.size() == 35);
  double err_o = 0, err_R = 0, err_E = 0, V_swing = 0;
  int next = 0;
  V5 g2 = V5::Zero();
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    while (next <= n_grid && next * grid <= v.t + 1e-12) {
      const mech::Sample s = v.at(std::max(v.t_prev, next * grid));
      const Point P = point(oracle[next].first, g2);
      g2 = P.th;
      for (int k = 0; k < 5; ++k) {
        const std::string b = "rod" + std::to_string(k + 1) + "_";
        const int ix = name_index(names, b + "x"), ie = name_index(names, b + "e0");
        err_o = std::max(err_o, (s.q.segment<3>(ix) - P.C.o[k]).cwiseAbs().maxCoeff());
        const Vector4d e = s.q.segment<4>(ie);
        const Eigen::Quaterniond qq(e[0], e[1], e[2], e[3]);
        err_R = std::max(err_R, (qq.toRotationMatrix() - P.C.R[k]).cwiseAbs().maxCoeff());
      }
      // the energy of pcsim's state: 1/2 qd^T M qd of the rods (centres and spins) + V
      double T = 0, V = 0;
      for (int k = 0; k < 5; ++k) {
        const std::string b = "rod" + std::to_string(k + 1) + "_";
        const int ix = name_index(names, b + "x"), ie = name_index(names, b + "e0");
        const Vector4d e = s.q.segment<4>(ie), ed = s.qd.segment<4>(ie);
        const Matrix3d A = Eigen::Quaterniond(e[0], e[1], e[2], e[3]).toRotationMatrix();
        const Vector3d wg = 2.0 * E_of(e) * ed;  // ground angular velocity
        const Vector3d c = s.q.segment<3>(ix) + A * (rod_vec[k] * 0.5);
        const Vector3d cv = s.qd.segment<3>(ix) + wg.cross(A * (rod_vec[k] * 0.5));
        Vector3d J(Jt, Jt, Jt);
        J[along[k]] = Ja;
        const Vector3d wb = A.transpose() * wg;
        T += 0.5 * mass_rod * cv.squaredNorm() + 0.5 * wb.dot(J.cwiseProduct(wb));
        V += mass_rod * grav * c[1];
      }
      V_swing = std::max(V_swing, std::abs(V - E0));
      err_E = std::max(err_E, std::abs(T + V - E0));
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("Bricard vs joint-angle model: max error origins " << err_o << " m, rotations " << err_R
                     << ", energy " << err_E << " J of a potential swing " << V_swing << " J");
  BOOST_TEST(next == n_grid + 1);
  BOOST_TEST(V_swing > 1.0);
  BOOST_TEST(err_o < 1e-6);
  BOOST_TEST(err_R < 1e-6);
  BOOST_TEST(err_E < 1e-6 * V_swing);
}

// R is unique although the split of it over the 30 joint rows is not: the joint tables written
// in three different orders, under names that sort differently (so the rows of g come in three
// different orders), give the same generalized R (and q_dd) to 1e-10 relative at the same
// consistent states (oracle points with nonzero rates), and each solve reports the 35 rows'
// rank 34 (nullity 1, indeterminate).
BOOST_AUTO_TEST_CASE(bricard_r_is_the_same_for_three_row_orders_of_the_joints) {
  const std::string text = model_text("bricard_a04.toml");
  // the six [model.joint.jK] tables, cut out of the text
  const auto first = text.find("[model.joint.j0]");
  const auto after = text.find("[model.force.gravity]");
  BOOST_REQUIRE(first != std::string::npos);
  BOOST_REQUIRE(after != std::string::npos);
  std::vector<std::string> table(6);
  for (int k = 0; k < 6; ++k) {
    const auto a = text.find("[model.joint.j" + std::to_string(k) + "]");
    const auto b = k < 5 ? text.find("[model.joint.j" + std::to_string(k + 1) + "]") : after;
    table[k] = text.substr(a, b - a);
  }
  const std::vector<std::vector<int>> orders = {{0, 1, 2, 3, 4, 5}, {5, 3, 1, 4, 0, 2}, {2, 4, 0, 5, 1, 3}};
  const std::vector<std::string> prefix = {"a", "b", "c", "d", "e", "f"};
  std::vector<std::vector<Eigen::VectorXd>> R(orders.size()), qdd(orders.size());
  std::vector<std::string> coords0;
  for (std::size_t o = 0; o < orders.size(); ++o) {
    std::string joints;
    for (std::size_t i = 0; i < orders[o].size(); ++i) {
      std::string t = table[orders[o][i]];
      const std::string old = "[model.joint.j" + std::to_string(orders[o][i]) + "]";
      // the i-th table gets a name that sorts i-th
      t.replace(0, old.size(), "[model.joint." + prefix[i] + "_j" + std::to_string(orders[o][i]) + "]");
      joints += t;
    }
    const std::string variant = text.substr(0, first) + joints + text.substr(after);
    const auto desc = load_model_text(variant, "bricard_a04_order" + std::to_string(o) + ".toml");
    const auto model = desc->instantiate({});
    if (o == 0) coords0 = desc->coordinates();
    BOOST_REQUIRE((desc->coordinates() == coords0));
    std::vector<int> rows;
    for (const auto& nm : desc->default_active_constraints()) rows.push_back(model->constraint_index(nm));
    BOOST_REQUIRE(rows.size() == 35u);
    if (o > 0) {  // the rows really come in another order
      const auto& c = desc->default_active_constraints();
      const bool renamed = std::find(c.begin(), c.end(), prefix[0] + "_j" + std::to_string(orders[o][0]) + "_x") != c.end();
      BOOST_TEST(renamed);
    }
    const mech::ActiveSet active = mech::ActiveSet::of(*model, rows);
    V5 guess = V5::Zero();
    for (const double th1 : {0.0, 0.25, -0.4, 0.6}) {
      const Point P = point(th1, guess);
      guess = P.th;
      Eigen::VectorXd q, qd;
      state_of(P, 1.3 - th1, coords0, q, qd);
      for (mech::ReactionMethod m : {mech::ReactionMethod::compatibility_structured, mech::ReactionMethod::compatibility}) {
        mech::Dynamics dyn(*model, Kernel::cpp);
        BOOST_REQUIRE((dyn.evaluate(active, 0.0, q, qd) == mech::ModelIssue::none));
        BOOST_REQUIRE((dyn.solve(m) == mech::ModelIssue::none));
        BOOST_TEST(dyn.rank == 34);
        BOOST_TEST(dyn.nullity == 1);
        BOOST_TEST(dyn.indeterminate());
        R[o].push_back(dyn.R);
        qdd[o].push_back(dyn.qdd);
      }
    }
  }
  double worst = 0;
  for (std::size_t o = 1; o < orders.size(); ++o)
    for (std::size_t i = 0; i < R[0].size(); ++i) {
      const double d = (R[o][i] - R[0][i]).norm() / R[0][i].norm();
      const double dq = (qdd[o][i] - qdd[0][i]).norm() / std::max(1.0, qdd[0][i].norm());
      worst = std::max({worst, d, dq});
      BOOST_TEST(d < 1e-10);
      BOOST_TEST(dq < 1e-10);
    }
  BOOST_TEST_MESSAGE("Bricard R over three row orders: worst relative difference " << worst);
}
