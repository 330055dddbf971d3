// The spatial slider-crank as bodies (models/slider_crank_spatial.toml: 15 coordinates, 14 rows:
// a revolute tree joint, a spherical, a universal and a prismatic joint) against an independent
// minimal-coordinate solution in the crank angle th, written here: the geometry in closed form,
//   P = (0, a cos th, a sin th)                         the crank pin
//   s = a cos th + sqrt(L^2 - b^2 - a^2 sin^2 th),  S = (b, s, 0)   the slider
//   rod axes: x_r = (S - P)/L, y_r = z x x_r/|z x x_r| (the universal joint's arm), z_r = x_r x y_r
// T = 1/2 m(th) th_d^2 with m(th) = Jc + ms s'^2 + mr |c'|^2 + w_b'^T Jr w_b' (c the rod's
// centre, w_b' the rod's body angular velocity per unit th_d, from R' R^T), V = g (mc z_cc +
// mr z_c), and Lagrange's equation m th_dd + 1/2 m' th_d^2 + V' = 0 integrated by RK4. The
// derivatives of the geometry are taken by complex steps (exact to rounding), m' by central
// differences of m (error ~1e-10).
#define BOOST_TEST_MODULE modelfile_slider_crank_spatial
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <complex>
#include <fstream>
#include <sstream>

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
using cd = std::complex<double>;

namespace {

const double a = 0.1, L = 0.4, b = 0.15, g = 9.81, mc = 0.5, mr = 1.0, ms = 2.0;
const Vector3d Jcrank(0.002, 0.0005, 0.002), Jrod(0.0005, 0.0135, 0.0135);

template <class T>
struct Geometry {
  Eigen::Matrix<T, 3, 1> P, S, c, cc;  // pin, slider, rod centre, crank centre of mass
  Eigen::Matrix<T, 3, 3> R;            // rod body -> ground
  T s;
};

// u x v without conjugation (Eigen's cross conjugates complex scalars; complex steps need none).
template <class T>
Eigen::Matrix<T, 3, 1> cross(const Eigen::Matrix<T, 3, 1>& u, const Eigen::Matrix<T, 3, 1>& v) {
  return Eigen::Matrix<T, 3, 1>(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]);
}

template <class T>
Geometry<T> geometry(T th) {
  using V = Eigen::Matrix<T, 3, 1>;
  Geometry<T> G;
  G.P = V(T(0), T(a) * cos(th), T(a) * sin(th));
  G.cc = V(T(0), T(a / 2) * cos(th), T(a / 2) * sin(th));
  G.s = T(a) * cos(th) + sqrt(T(L * L - b * b) - T(a * a) * sin(th) * sin(th));
  G.S = V(T(b), G.s, T(0));
  G.c = (G.P + G.S) * T(0.5);
  const V x = (G.S - G.P) / T(L);
  V y = cross(V(T(0), T(0), T(1)), x);
  y /= sqrt(y.cwiseProduct(y).sum());  // no conjugation: complex steps
  const V z = cross(x, y);
  G.R.col(0) = x;
  G.R.col(1) = y;
  G.R.col(2) = z;
  return G;
}

struct Derived {
  Geometry<double> G;
  double s_d;          // ds/dth
  Vector3d c_d, w_b;   // rod centre and body angular velocity per unit th_d
  double V_d;          // dV/dth
};

Derived derived(double th) {
  const double h = 1e-30;
  const Geometry<cd> Gc = geometry(cd(th, h));
  Derived D;
  D.G = geometry(th);
  D.s_d = Gc.s.imag() / h;
  D.c_d = Gc.c.imag() / h;
  const Matrix3d Rd = Gc.R.imag() / h;
  const Matrix3d W = Rd * D.G.R.transpose();  // skew(w)
  const Vector3d w(0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1)));
  D.w_b = D.G.R.transpose() * w;
  D.V_d = g * (mc * Gc.cc[2].imag() / h + mr * Gc.c[2].imag() / h);
  return D;
}

double mass(double th) {
  const Derived D = derived(th);
  const double Jc = Jcrank[0] + mc * (a / 2) * (a / 2);  // about the crank's axis (x)
  return Jc + ms * D.s_d * D.s_d + mr * D.c_d.squaredNorm() + D.w_b.dot(Jrod.cwiseProduct(D.w_b));
}

// th_dd from Lagrange's equation in th.
double acceleration(double th, double thd) {
  const double e = 1e-6;
  const double md = (mass(th + e) - mass(th - e)) / (2 * e);
  return -(0.5 * md * thd * thd + derived(th).V_d) / mass(th);
}

Eigen::Matrix<double, 3, 4> E_of(const Vector4d& e) {
  Eigen::Matrix<double, 3, 4> E;
  E << -e[1], e[0], -e[3], e[2], -e[2], e[3], e[0], -e[1], -e[3], -e[2], e[1], e[0];
  return E;
}
Vector4d e_of_matrix(const Matrix3d& A) {
  const Eigen::Quaterniond q(A);
  Vector4d e(q.w(), q.x(), q.y(), q.z());
  return e[0] < 0 ? Vector4d(-e) : e;
}

}  // namespace

// From th = 0.3 rad, th_d = 6 rad/s (the crank turning over the top ~3 times in 2 s, under
// gravity), pcsim at rtol = 1e-10 must give th(t) and the slider's s(t) of the oracle (RK4,
// h = 1e-4 s: its energy drifts by 3e-10) to 1e-7, the rod's orientation to 1e-7, and keep the
// energy 1/2 m(th) th_d^2 + V(th) of the oracle's formula (evaluated at pcsim's th, th_d) to
// 2e-7 relative. Measured: th 3e-8 rad, s 2e-9 m, rotation 8e-9, energy 8e-8.
BOOST_AUTO_TEST_CASE(spatial_slider_crank_follows_the_minimal_coordinate_solution) {
  const auto desc = load_model_file(model_path("slider_crank_spatial.toml"));
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  auto idx = [&](const std::string& n) {
    const auto it = std::find(names.begin(), names.end(), n);
    BOOST_REQUIRE(it != names.end());
    return static_cast<int>(it - names.begin());
  };
  const double th0 = 0.3, thd0 = 6.0;
  const Derived D = derived(th0);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = Eigen::VectorXd::Zero(model->n());
  q[idx("th")] = th0;
  qd[idx("th")] = thd0;
  const Vector4d er = e_of_matrix(D.G.R);
  for (int i = 0; i < 3; ++i) {
    q[idx(std::string("rod_") + "xyz"[i])] = D.G.c[i];
    qd[idx(std::string("rod_") + "xyz"[i])] = D.c_d[i] * thd0;
  }
  const Vector3d w = D.G.R * D.w_b * thd0;
  const Vector4d erd = 0.5 * E_of(er).transpose() * w;
  for (int i = 0; i < 4; ++i) {
    q[idx("rod_e" + std::to_string(i))] = er[i];
    qd[idx("rod_e" + std::to_string(i))] = erd[i];
  }
  q[idx("slider_x")] = b;
  q[idx("slider_y")] = D.G.s;
  qd[idx("slider_y")] = D.s_d * thd0;
  q[idx("slider_e0")] = 1.0;

  // The oracle on a grid of 1e-3 s.
  const double t_end = 2.0, grid = 1e-3;
  const int n_grid = static_cast<int>(std::lround(t_end / grid)), sub = 10;
  std::vector<std::pair<double, double>> oracle(n_grid + 1);
  double th = th0, thd = thd0;
  oracle[0] = {th, thd};
  const double h = grid / sub;
  for (int k = 1; k <= n_grid; ++k) {
    for (int j = 0; j < sub; ++j) {
      const double k1x = thd, k1v = acceleration(th, thd);
      const double k2x = thd + 0.5 * h * k1v, k2v = acceleration(th + 0.5 * h * k1x, k2x);
      const double k3x = thd + 0.5 * h * k2v, k3v = acceleration(th + 0.5 * h * k2x, k3x);
      const double k4x = thd + h * k3v, k4v = acceleration(th + h * k3x, k4x);
      th += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      thd += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    oracle[k] = {th, thd};
  }
  auto energy = [&](double t, double td) {
    const Derived d = derived(t);
    return 0.5 * mass(t) * td * td + g * (mc * d.G.cc[2] + mr * d.G.c[2]);
  };
  const double E0 = energy(th0, thd0);
  BOOST_TEST_MESSAGE("oracle: th from " << th0 << " to " << th << " rad; energy drift "
                     << std::abs(energy(th, thd) - E0) / E0);

  mech::SimulationOptions o;
  o.t_end = t_end;
  o.rtol = o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = desc->default_active_constraints();
  double err_th = 0, err_s = 0, err_R = 0, err_E = 0;
  int next = 0;
  const int ith = idx("th"), isy = idx("slider_y"), ie = idx("rod_e0");
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    while (next <= n_grid && next * grid <= v.t + 1e-12) {
      const mech::Sample s = v.at(std::max(v.t_prev, next * grid));
      const auto [tho, thdo] = oracle[next];
      const Derived d = derived(tho);
      err_th = std::max(err_th, std::abs(s.q[ith] - tho));
      err_s = std::max(err_s, std::abs(s.q[isy] - d.G.s));
      const Vector4d e = s.q.segment<4>(ie);
      const Eigen::Quaterniond qq(e[0], e[1], e[2], e[3]);
      err_R = std::max(err_R, (qq.toRotationMatrix() - d.G.R).cwiseAbs().maxCoeff());
      err_E = std::max(err_E, std::abs(energy(s.q[ith], s.qd[ith]) - E0) / std::abs(E0));
      ++next;
    }
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("spatial slider-crank vs minimal coordinates: max error th " << err_th << " rad, s "
                     << err_s << " m, rod rotation " << err_R << ", energy rel " << err_E);
  BOOST_TEST(next == n_grid + 1);
  BOOST_TEST(err_th < 1e-7);
  BOOST_TEST(err_s < 1e-7);
  BOOST_TEST(err_R < 1e-7);
  BOOST_TEST(err_E < 2e-7);
}

// Inverse dynamics of the closed loop: a drive holds the crank at th = 0.3 + 6 t (a row of the
// tree joint's angle); its multiplier, the column M_motor_z, is the torque that keeps the crank
// turning uniformly, by the minimal-coordinate equation with th_dd = 0:
// tau = 1/2 m'(th) w^2 + V'(th), to 1e-7 N m over one turn.
BOOST_AUTO_TEST_CASE(drive_torque_of_the_spatial_slider_crank_is_the_inverse_dynamics) {
  std::ifstream in(model_path("slider_crank_spatial.toml"));
  std::stringstream text;
  text << in.rdbuf()
       << "\n[model.joint.motor]\ntype = \"drive\"\njoint = \"crank_axle\"\nmotion = \"0.3 + 6*t\"\n";
  const auto desc = load_model_text(text.str(), "slider_crank_spatial_driven.toml");
  const auto model = desc->instantiate({});
  const auto& names = desc->coordinates();
  auto idx = [&](const std::string& n) {
    const auto it = std::find(names.begin(), names.end(), n);
    BOOST_REQUIRE(it != names.end());
    return static_cast<int>(it - names.begin());
  };
  int mz = -1;
  for (std::size_t i = 0; i < desc->outputs().size(); ++i)
    if (desc->outputs()[i].name == "M_motor_z") mz = static_cast<int>(i);
  BOOST_REQUIRE(mz >= 0);
  const double th0 = 0.3, w = 6.0;
  const Derived D = derived(th0);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = Eigen::VectorXd::Zero(model->n());
  q[idx("th")] = th0;
  qd[idx("th")] = w;
  const Vector4d er = e_of_matrix(D.G.R);
  const Vector4d erd = 0.5 * E_of(er).transpose() * (D.G.R * D.w_b * w);
  for (int i = 0; i < 3; ++i) {
    q[idx(std::string("rod_") + "xyz"[i])] = D.G.c[i];
    qd[idx(std::string("rod_") + "xyz"[i])] = D.c_d[i] * w;
  }
  for (int i = 0; i < 4; ++i) {
    q[idx("rod_e" + std::to_string(i))] = er[i];
    qd[idx("rod_e" + std::to_string(i))] = erd[i];
  }
  q[idx("slider_x")] = b;
  q[idx("slider_y")] = D.G.s;
  qd[idx("slider_y")] = D.s_d * w;
  q[idx("slider_e0")] = 1.0;
  mech::SimulationOptions o;
  o.t_end = 2 * M_PI / w;
  o.rtol = o.atol = 1e-10;
  o.kernel = Kernel::cpp;
  o.active_constraints = desc->default_active_constraints();
  double err = 0, tau_max = 0;
  const int ith = idx("th");
  const auto r = mech::simulate(*model, q, qd, o, [&](const mech::StepView& v) {
    const mech::Sample& s = v.sample(v.t);
    const double th = s.q[ith], e = 1e-6;
    const double md = (mass(th + e) - mass(th - e)) / (2 * e);
    const double tau = 0.5 * md * w * w + derived(th).V_d;
    err = std::max(err, std::abs(s.derived[mz] - tau));
    tau_max = std::max(tau_max, std::abs(tau));
    return true;
  });
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST_MESSAGE("drive torque: max |tau| " << tau_max << " N m, max error " << err << " N m");
  BOOST_TEST(tau_max > 0.1);
  BOOST_TEST(err < 1e-7);
}
