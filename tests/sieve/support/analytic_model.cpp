// The hand-derived sieve model (see analytic_model.hpp).
//
// T of (3.4) (repaired) is T = ½ q̇ᵀ M(q, t) q̇ + a(q, t)ᵀ q̇ + ½ J0 ω², so Lagrange's left side
// is M q̈ + h with
//   h_j = Σ_k (Σ_i ∂M_jk/∂q_i q̇_i + ∂M_jk/∂t) q̇_k + Σ_i ∂a_j/∂q_i q̇_i + ∂a_j/∂t
//         − ½ q̇ᵀ (∂M/∂q_j) q̇ − (∂a/∂q_j)ᵀ q̇.
// M depends on θ, s, u and t only; a on θ and t only. The partials below are differentiated
// by hand from (3.4); the tests compare every entry with the AD-derived models.
#include "sieve/support/analytic_model.hpp"

#include <cmath>
#include <limits>

namespace pcsim::sieve {

namespace {

enum { X = 0, Y = 1, TH = 2, S = 3, U = 4, PHI = 5 };
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

class SieveAnalyticModel final : public mech::Model {
 public:
  explicit SieveAnalyticModel(const SieveCommon& c) : c_(c) {
    name_ = "sieve (closed form, analytic derivatives)";
    coordinates_ = c.coordinates();
    constraints_ = c.constraints();
    derived_names_ = c.derived_names();
  }

  void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& M_out, Eigen::VectorXd& h_out) const override {
    const SieveParameters& p = c_.p;
    const double th = q(TH), s = q(S), u = q(U);
    const double c = std::cos(th), sn = std::sin(th);
    const double wt = p.omega * t, psi = wt + th;
    const double sp = std::sin(psi), cp = std::cos(psi);
    const double E = p.y0 * std::sin(wt) - p.x0 * std::cos(wt);
    const double Et = p.omega * (p.y0 * std::cos(wt) + p.x0 * std::sin(wt));  // dE/dt
    const double m_all = p.m0 + p.m1 + p.m2, m0e = p.m0 * p.e, m2 = p.m2;
    const double l0sq = p.x0 * p.x0 + p.y0 * p.y0 + p.e * p.e;
    // Coefficients of ẋθ̇ (A) and ẏθ̇ (B) in T; note ∂A/∂θ = B and ∂B/∂θ = −A.
    const double A = p.m0 * (p.y0 * c - p.x0 * sn + p.e * sp) + m2 * (s * c - u * sn);
    const double B = -(p.m0 * (p.x0 * c + p.y0 * sn - p.e * cp) + m2 * (s * sn + u * c));

    Mat6 M = Mat6::Zero();
    M(X, X) = M(Y, Y) = m_all;
    M(TH, TH) = p.J0 + p.J1 + p.J2 + p.m0 * l0sq + 2 * m0e * E + m2 * (s * s + u * u);
    M(S, S) = M(U, U) = m2;
    M(PHI, PHI) = p.J2;
    auto sym = [&M](int i, int j, double v) { M(i, j) = M(j, i) = v; };
    sym(X, TH, A);
    sym(Y, TH, B);
    sym(X, S, m2 * sn);
    sym(X, U, m2 * c);
    sym(Y, S, m2 * c);
    sym(Y, U, -m2 * sn);
    sym(TH, S, -m2 * u);
    sym(TH, U, m2 * s);
    sym(TH, PHI, p.J2);

    // ∂M/∂θ, ∂M/∂s, ∂M/∂u, ∂M/∂t (only the non-zero entries).
    Mat6 Mth = Mat6::Zero(), Ms = Mat6::Zero(), Mu = Mat6::Zero(), Mt = Mat6::Zero();
    auto sym_in = [](Mat6& D, int i, int j, double v) { D(i, j) = D(j, i) = v; };
    sym_in(Mth, X, TH, B);
    sym_in(Mth, Y, TH, -A);
    sym_in(Mth, X, S, m2 * c);
    sym_in(Mth, X, U, -m2 * sn);
    sym_in(Mth, Y, S, -m2 * sn);
    sym_in(Mth, Y, U, -m2 * c);
    Ms(TH, TH) = 2 * m2 * s;
    sym_in(Ms, X, TH, m2 * c);
    sym_in(Ms, Y, TH, -m2 * sn);
    sym_in(Ms, TH, U, m2);
    Mu(TH, TH) = 2 * m2 * u;
    sym_in(Mu, X, TH, -m2 * sn);
    sym_in(Mu, Y, TH, -m2 * c);
    sym_in(Mu, TH, S, -m2);
    Mt(TH, TH) = 2 * m0e * Et;
    sym_in(Mt, X, TH, m0e * p.omega * cp);
    sym_in(Mt, Y, TH, -m0e * p.omega * sp);

    // a = (m0 e ω sin ψ, m0 e ω cos ψ, (J0 + m0 e E) ω, 0, 0, 0) and its partials.
    Vec6 a_th = Vec6::Zero(), a_t = Vec6::Zero();
    a_th(X) = m0e * p.omega * cp;
    a_th(Y) = -m0e * p.omega * sp;
    a_t(X) = m0e * p.omega * p.omega * cp;
    a_t(Y) = -m0e * p.omega * p.omega * sp;
    a_t(TH) = m0e * p.omega * Et;

    const Vec6 v = qd.head<6>();
    const Mat6 Mdot = Mth * v(TH) + Ms * v(S) + Mu * v(U) + Mt;
    Vec6 h = Mdot * v + a_th * v(TH) + a_t;
    h(TH) -= 0.5 * v.dot(Mth * v) + a_th.dot(v);
    h(S) -= 0.5 * v.dot(Ms * v);
    h(U) -= 0.5 * v.dot(Mu * v);
    M_out = M;
    h_out = h;
  }

  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override {
    Q = closed_.applied_forces<double>(q, qd, t);
  }

  void constraint_rows(const std::vector<int>& active, double /*t*/, const Eigen::VectorXd& /*q*/,
                       const Eigen::VectorXd& /*qd*/, Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                       Eigen::VectorXd& gamma) const override {
    for (std::size_t r = 0; r < active.size(); ++r) {
      const Eigen::Index i = static_cast<Eigen::Index>(r);
      g.row(i).setZero();
      switch (active[r]) {
        case 0: g(i, U) = 1.0; break;                             // contact: u − u0
        case 1: case 2: g(i, S) = 1.0; g(i, PHI) = c_.p.r; break;  // rolling (both forms)
        case 4: g(i, S) = 1.0; g(i, PHI) = -c_.p.r; break;          // rolling_printed
        default: g(i, TH) = 1.0; break;                           // lock_theta: θ
      }
      g0(i) = 0.0;     // no explicit time dependence
      gamma(i) = 0.0;  // constant rows: ġ q̇ + ġ0 = 0
    }
  }

  double position_residual(int i, double t, const Eigen::VectorXd& q) const override {
    if (i == 2) return std::numeric_limits<double>::quiet_NaN();  // velocity form
    return c_.holonomic<double>(i, q, t);
  }

  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& /*qdd*/, const Eigen::VectorXd& R,
               Eigen::VectorXd& out) const override {
    c_.derived(t, q, qd, R, out);
  }

 private:
  SieveCommon c_;
  SieveClosedForm closed_{c_};
};

}  // namespace

std::shared_ptr<const mech::Model> make_analytic_sieve_model(const SieveCommon& common) {
  return std::make_shared<const SieveAnalyticModel>(common);
}

}  // namespace pcsim::sieve
