// Internal: the definition of make_model(), i.e. the automatic differentiation (Eigen's
// AutoDiffScalar, nested, with small-buffer derivative vectors) that turns a model struct into
// M, h, Q, g, g0 and ġq̇ + ġ0. Included by mech/model.hpp; not for direct use.
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <unsupported/Eigen/AutoDiff>

#include "common/error.hpp"

namespace pcsim::mech::detail {

// Derivative vectors: dynamic size, but stored in a fixed buffer (no heap allocation).
// Inner level: up to 2n+1 directions (q, q̇, t); outer level: up to n directions (q̇).
inline constexpr int kMaxInner = 2 * kMaxCoordinates + 1;
using InnerDer = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxInner, 1>;
using AD1 = Eigen::AutoDiffScalar<InnerDer>;
using OuterDer = Eigen::Matrix<AD1, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxCoordinates, 1>;
using AD2 = Eigen::AutoDiffScalar<OuterDer>;

// ---- detection of the optional members of a model struct ----------------------------------
template <class, class = void> struct has_dissipation : std::false_type {};
template <class I>
struct has_dissipation<I, std::void_t<decltype(std::declval<const I&>().dissipation(
                              std::declval<const VecX<double>&>(), std::declval<const VecX<double>&>(),
                              std::declval<const double&>()))>> : std::true_type {};
template <class, class = void> struct has_applied_forces : std::false_type {};
template <class I>
struct has_applied_forces<I, std::void_t<decltype(std::declval<const I&>().applied_forces(
                                 std::declval<const VecX<double>&>(), std::declval<const VecX<double>&>(),
                                 std::declval<const double&>()))>> : std::true_type {};
template <class, class = void> struct has_constraints : std::false_type {};
template <class I>
struct has_constraints<I, std::void_t<decltype(std::declval<const I&>().constraints())>>
    : std::true_type {};
template <class, class = void> struct has_holonomic : std::false_type {};
template <class I>
struct has_holonomic<I, std::void_t<decltype(std::declval<const I&>().holonomic(
                            0, std::declval<const VecX<double>&>(), std::declval<const double&>()))>>
    : std::true_type {};
template <class, class = void> struct has_velocity_form : std::false_type {};
template <class I>
struct has_velocity_form<I, std::void_t<decltype(std::declval<const I&>().velocity_form(
                                0, std::declval<const VecX<double>&>(), std::declval<const double&>(),
                                std::declval<VecX<double>&>(), std::declval<double&>()))>>
    : std::true_type {};
template <class, class = void> struct has_derived : std::false_type {};
template <class I>
struct has_derived<I, std::void_t<decltype(std::declval<const I&>().derived_names()),
                                  decltype(std::declval<const I&>().derived(
                                      0.0, std::declval<const Eigen::VectorXd&>(),
                                      std::declval<const Eigen::VectorXd&>(),
                                      std::declval<const Eigen::VectorXd&>(),
                                      std::declval<Eigen::VectorXd&>()))>> : std::true_type {};

// Component k of a derivative vector; an expression that did not depend on the seeded
// variables may carry an empty derivative vector, which means zero.
template <class V> inline auto der_at(const V& v, int k) -> typename V::Scalar {
  return k < v.size() ? v[k] : typename V::Scalar(0);
}
inline AD1 ad1_const(double value, int m) { return AD1(value, InnerDer::Zero(m)); }
inline AD1 ad1_var(double value, int m, int k) { return AD1(value, InnerDer::Unit(m, k)); }

template <class Impl>
class AutoDiffModel final : public Model {
 public:
  explicit AutoDiffModel(Impl impl) : impl_(std::move(impl)) {
    name_ = impl_.name();
    coordinates_ = impl_.coordinates();
    if (coordinates_.empty() || static_cast<int>(coordinates_.size()) > kMaxCoordinates) {
      throw InputError("model '" + name_ + "': " + std::to_string(coordinates_.size()) +
                       " coordinates; a model needs 1.." + std::to_string(kMaxCoordinates));
    }
    if constexpr (has_constraints<Impl>::value) constraints_ = impl_.constraints();
    if constexpr (has_derived<Impl>::value) derived_names_ = impl_.derived_names();
  }

  void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& M, Eigen::VectorXd& h) const override {
    const int n = this->n();
    const int m = 2 * n + 1;  // inner directions: q (n), q̇ (n), t (1)
    VecX<AD2> Q2(n), QD2(n);
    OuterDer zero_outer(n);
    for (int k = 0; k < n; ++k) zero_outer[k] = ad1_const(0.0, m);
    for (int i = 0; i < n; ++i) {
      Q2[i] = AD2(ad1_var(q[i], m, i), zero_outer);
      OuterDer seed = zero_outer;
      seed[i] = ad1_const(1.0, m);
      QD2[i] = AD2(ad1_var(qd[i], m, n + i), seed);
    }
    const AD2 T2(ad1_var(t, m, 2 * n), zero_outer);
    const AD2 T = impl_.kinetic_energy(Q2, QD2, T2);
    const auto& dT = T.value().derivatives();  // ∂T/∂(q, q̇, t)
    for (int j = 0; j < n; ++j) {
      const AD1 pj = der_at(T.derivatives(), j);  // ∂T/∂q̇_j and its derivatives
      const auto& d2 = pj.derivatives();
      double hj = der_at(d2, 2 * n) - der_at(dT, j);
      for (int k = 0; k < n; ++k) {
        M(j, k) = der_at(d2, n + k);
        hj += der_at(d2, k) * qd[k];
      }
      h[j] = hj;
    }
  }

  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override {
    const int n = this->n();
    VecX<AD1> qa(n);
    for (int i = 0; i < n; ++i) qa[i] = ad1_var(q[i], n, i);
    const AD1 ta = ad1_const(t, n);
    const AD1 V = impl_.potential_energy(qa, ta);
    for (int i = 0; i < n; ++i) Q[i] = -der_at(V.derivatives(), i);
    if constexpr (has_dissipation<Impl>::value) {
      VecX<AD1> qc(n), qda(n);
      for (int i = 0; i < n; ++i) {
        qc[i] = ad1_const(q[i], n);
        qda[i] = ad1_var(qd[i], n, i);
      }
      const AD1 F = impl_.dissipation(qc, qda, ta);
      for (int i = 0; i < n; ++i) Q[i] -= der_at(F.derivatives(), i);
    }
    if constexpr (has_applied_forces<Impl>::value) {
      const VecX<double> extra = impl_.applied_forces(q, qd, t);
      if (extra.size() == n) {
        Q += extra;
      } else {
        Q.setConstant(std::numeric_limits<double>::quiet_NaN());  // wrong size: reported as non-finite
      }
    }
  }

  void constraint_rows(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& qd, Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                       Eigen::VectorXd& gamma) const override {
    for (std::size_t r = 0; r < active.size(); ++r) {
      const int i = active[r];
      if (constraints_[i].kind == ConstraintKind::holonomic) {
        holonomic_row(i, t, q, qd, g, g0, gamma, static_cast<int>(r));
      } else {
        velocity_row(i, t, q, qd, g, g0, gamma, static_cast<int>(r));
      }
    }
  }

  double position_residual(int i, double t, const Eigen::VectorXd& q) const override {
    if constexpr (has_holonomic<Impl>::value) {
      if (constraints_[i].kind == ConstraintKind::holonomic) return impl_.holonomic(i, q, t);
    }
    return std::numeric_limits<double>::quiet_NaN();
  }

  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& R, Eigen::VectorXd& out) const override {
    if constexpr (has_derived<Impl>::value) {
      impl_.derived(t, q, qd, R, out);
    } else {
      out.resize(0);
    }
  }

 private:
  // Φ_i with inner directions (q, t) and one outer direction d = (q̇, 1):
  // value.derivatives() = (g_i, g0_i); derivatives()[0].derivatives()·d = dᵀ ∇²Φ d = γ_i.
  void holonomic_row(int i, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& g, Eigen::VectorXd& g0, Eigen::VectorXd& gamma, int r) const {
    if constexpr (has_holonomic<Impl>::value) {
      const int n = this->n();
      const int m = n + 1;
      VecX<AD2> qa(n);
      for (int k = 0; k < n; ++k) {
        OuterDer d(1);
        d[0] = ad1_const(qd[k], m);
        qa[k] = AD2(ad1_var(q[k], m, k), d);
      }
      OuterDer dt(1);
      dt[0] = ad1_const(1.0, m);
      const AD2 ta(ad1_var(t, m, n), dt);
      const AD2 phi = impl_.holonomic(i, qa, ta);
      const auto& grad = phi.value().derivatives();
      const AD1 dphi = der_at(phi.derivatives(), 0);
      const auto& hd = dphi.derivatives();
      double gam = der_at(hd, n);
      for (int k = 0; k < n; ++k) {
        g(r, k) = der_at(grad, k);
        gam += der_at(hd, k) * qd[k];
      }
      g0[r] = der_at(grad, n);
      gamma[r] = gam;
    } else {
      g.row(r).setConstant(std::numeric_limits<double>::quiet_NaN());
      g0[r] = gamma[r] = std::numeric_limits<double>::quiet_NaN();
    }
  }

  // Row (g_i, g0_i) evaluated with one direction d = (q̇, 1) in (q, t):
  // γ_i = (dg_i/dd) q̇ + dg0_i/dd.
  void velocity_row(int i, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                    Eigen::MatrixXd& g, Eigen::VectorXd& g0, Eigen::VectorXd& gamma, int r) const {
    if constexpr (has_velocity_form<Impl>::value) {
      const int n = this->n();
      VecX<AD1> qa(n);
      for (int k = 0; k < n; ++k) qa[k] = AD1(q[k], InnerDer::Constant(1, qd[k]));
      const AD1 ta(t, InnerDer::Constant(1, 1.0));
      VecX<AD1> row(n);
      for (int k = 0; k < n; ++k) row[k] = ad1_const(0.0, 1);
      AD1 c = ad1_const(0.0, 1);
      impl_.velocity_form(i, qa, ta, row, c);
      double gam = der_at(c.derivatives(), 0);
      for (int k = 0; k < n; ++k) {
        g(r, k) = row[k].value();
        gam += der_at(row[k].derivatives(), 0) * qd[k];
      }
      g0[r] = c.value();
      gamma[r] = gam;
    } else {
      g.row(r).setConstant(std::numeric_limits<double>::quiet_NaN());
      g0[r] = gamma[r] = std::numeric_limits<double>::quiet_NaN();
    }
  }

  Impl impl_;
};

}  // namespace pcsim::mech::detail

namespace pcsim::mech {

template <class Impl> std::shared_ptr<const Model> make_model(Impl impl) {
  return std::make_shared<const detail::AutoDiffModel<Impl>>(std::move(impl));
}

}  // namespace pcsim::mech
