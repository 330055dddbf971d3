// The variational equations on ode_integrate (see variational.hpp).
#include "steady/variational.hpp"

#include <cmath>
#include <exception>
#include <sstream>

#include "mech/simulation.hpp"
#include "mech/tangent.hpp"

namespace pcsim::steady {

namespace {

// The augmented state, ordered for the second-order structure (RADAU5's M1 = M2 = n (1 + m)):
//   positions  P = [q | Yq_0 | ... | Yq_{m-1}]        (n each)
//   velocities V = [q̇ | Yq̇_0 | ... | Yq̇_{m-1}]       (n each)
//   quadratures    [w (nq) | W (nq x m, row-major) | Cint (nc x nc, row-major) | means]
// so that P' = V exactly and Radau's linear systems have the order of the velocity part.
class Augmented {
 public:
  Augmented(const VariationalSetup& s, int m)
      : s_(s),
        set_(mech::ActiveSet::of(*s.model, s.active)),
        tan_(*s.model),
        jac_(*s.model),
        n_(s.model->n()),
        m_(m),
        N_(n_ * (1 + m)),
        nq_(static_cast<int>(s.quadrature.size())),
        nc_(static_cast<int>(s.inverse_mass_quadrature.size())),
        nm_(static_cast<int>(s.means.size())) {
    q_.resize(n_);
    qd_.resize(n_);
    V_.setZero(2 * n_ + 1, m_);
    // Only the columns with a force need the constrained response.
    for (int j = 0; j < m_ && s.forces.cols() == m_; ++j)
      if (s.forces.col(j).cwiseAbs().maxCoeff() > 0) force_cols_.push_back(j);
    has_forces_ = !force_cols_.empty();
    const int nf = static_cast<int>(force_cols_.size());
    if (has_forces_ || nc_ > 0) {
      B_.setZero(n_, nf + nc_);
      for (int c = 0; c < nf; ++c) B_.col(c) = s.forces.col(force_cols_[c]);
      for (int a = 0; a < nc_; ++a) B_(s.inverse_mass_quadrature[a], nf + a) = 1.0;
    }
  }

  int size() const { return 2 * N_ + nq_ + nq_ * m_ + nc_ * nc_ + nm_; }
  int N() const { return N_; }
  int quad_offset() const { return 2 * N_; }

  bool rhs(double t, const double* y, double* out) {
    try {
      return rhs_impl(t, y, out);
    } catch (const std::exception& e) {
      failure_ = e.what();
      return false;
    }
  }

  bool rhs_impl(double t, const double* y, double* out) {
    const int n = n_;
    q_ = Eigen::Map<const Eigen::VectorXd>(y, n);
    qd_ = Eigen::Map<const Eigen::VectorXd>(y + N_, n);
    for (int j = 0; j < m_; ++j) {
      V_.col(j).head(n) = Eigen::Map<const Eigen::VectorXd>(y + (1 + j) * n, n);
      V_.col(j).segment(n, n) = Eigen::Map<const Eigen::VectorXd>(y + N_ + (1 + j) * n, n);
    }
    if (tan_.evaluate(set_, t, q_, qd_, V_) != mech::ModelIssue::none) {
      failure_ = tan_.message();
      return false;
    }
    // Positions: P' = V.
    for (int i = 0; i < N_; ++i) out[i] = y[N_ + i];
    Eigen::Map<Eigen::VectorXd>(out + N_, n) = tan_.qdd;
    for (int j = 0; j < m_; ++j) Eigen::Map<Eigen::VectorXd>(out + N_ + (1 + j) * n, n) = tan_.dqdd.col(j);
    if (B_.cols() > 0) {
      tan_.respond(B_, X_);
      for (std::size_t c = 0; c < force_cols_.size(); ++c)
        Eigen::Map<Eigen::VectorXd>(out + N_ + (1 + force_cols_[c]) * n, n) += X_.col(static_cast<Eigen::Index>(c));
    }
    if (s_.parameter_term && s_.parameter_column >= 0) {
      if (!s_.parameter_term(t, q_, qd_, dp_)) {
        failure_ = "the parameter derivative of the right-hand side could not be evaluated";
        return false;
      }
      Eigen::Map<Eigen::VectorXd>(out + N_ + (1 + s_.parameter_column) * n, n) += dp_;
    }
    double* quad = out + 2 * N_;
    for (int k = 0; k < nq_; ++k) {
      const int i = s_.quadrature[k];
      quad[k] = y[i];
      for (int j = 0; j < m_; ++j) quad[nq_ + k * m_ + j] = y[(1 + j) * n + i];
    }
    double* cq = quad + nq_ + nq_ * m_;
    const int c0 = static_cast<int>(force_cols_.size());
    for (int a = 0; a < nc_; ++a)
      for (int b = 0; b < nc_; ++b) cq[a * nc_ + b] = X_(s_.inverse_mass_quadrature[a], c0 + b);
    double* mq = cq + nc_ * nc_;
    for (int k = 0; k < nm_; ++k) mq[k] = y[s_.means[k]];
    return true;
  }

  // Block-diagonal Jacobian of the augmented system: ∂f/∂y in the (q, q̇) block of every
  // column. The coupling of the sensitivities to y (second derivatives) and of the force
  // responses is left out: the exact Jacobian is block lower triangular with these diagonal
  // blocks, so Radau's simplified Newton still converges (the neglected part is nilpotent).
  bool jacobian(double t, const double* y, double* J) {
    try {
      const int n = n_, A = size();
      q_ = Eigen::Map<const Eigen::VectorXd>(y, n);
      qd_ = Eigen::Map<const Eigen::VectorXd>(y + N_, n);
      if (jac_.jacobian(set_, t, q_, qd_, Jf_) != mech::ModelIssue::none) {
        failure_ = jac_.message();
        return false;
      }
      Eigen::Map<Eigen::MatrixXd> Ja(J, A, A);
      Ja.setZero();
      for (int i = 0; i < N_; ++i) Ja(i, N_ + i) = 1.0;
      for (int c = 0; c <= m_; ++c) {
        Ja.block(N_ + c * n, c * n, n, n) = Jf_.block(n, 0, n, n);
        Ja.block(N_ + c * n, N_ + c * n, n, n) = Jf_.block(n, n, n, n);
      }
      for (int k = 0; k < nq_; ++k) {
        const int i = s_.quadrature[k];
        Ja(2 * N_ + k, i) = 1.0;
        for (int j = 0; j < m_; ++j) Ja(2 * N_ + nq_ + k * m_ + j, (1 + j) * n + i) = 1.0;
      }
      for (int k = 0; k < nm_; ++k) Ja(2 * N_ + nq_ + nq_ * m_ + nc_ * nc_ + k, s_.means[k]) = 1.0;
      return true;
    } catch (const std::exception& e) {
      failure_ = e.what();
      return false;
    }
  }

  const std::string& failure() const { return failure_; }

 private:
  const VariationalSetup& s_;
  mech::ActiveSet set_;
  mech::RhsTangent tan_, jac_;
  int n_, m_, N_, nq_, nc_, nm_;
  bool has_forces_ = false;
  std::vector<int> force_cols_;  ///< sensitivity columns with a force (their B_ columns first)
  Eigen::VectorXd q_, qd_, dp_;
  Eigen::MatrixXd V_, B_, X_, Jf_;
  std::string failure_;
};

}  // namespace

VariationalResult integrate_variational(const VariationalSetup& setup, double t0, double t1,
                                        const Eigen::VectorXd& y0, const Eigen::MatrixXd& Y0,
                                        const VariationalOptions& options) {
  VariationalResult res;
  res.t = t0;
  if (!setup.model) {
    res.message = "no model";
    return res;
  }
  const int n = setup.model->n();
  const int m = static_cast<int>(Y0.cols());
  if (y0.size() != 2 * n || (m > 0 && Y0.rows() != 2 * n)) {
    res.message = "integrate_variational: y0 must have 2n entries and Y0 2n rows";
    return res;
  }
  std::unique_ptr<Augmented> aug;
  try {
    aug = std::make_unique<Augmented>(setup, m);
  } catch (const std::exception& e) {
    res.message = e.what();
    return res;
  }
  const int N = aug->N(), A = aug->size();
  Eigen::VectorXd ya = Eigen::VectorXd::Zero(A);
  ya.head(n) = y0.head(n);
  ya.segment(N, n) = y0.tail(n);
  for (int j = 0; j < m; ++j) {
    ya.segment((1 + j) * n, n) = Y0.col(j).head(n);
    ya.segment(N + (1 + j) * n, n) = Y0.col(j).tail(n);
  }

  OdeProblem p;
  p.n = A;
  p.rhs = [&aug](double t, const double* y, double* f) { return aug->rhs(t, y, f); };
  p.jacobian = [&aug](double t, const double* y, double* J) { return aug->jacobian(t, y, J); };
  p.second_order_count = N;
  p.second_order_stride = N;

  mech::SimulationOptions engine;
  engine.kernel = options.kernel;
  engine.rtol = options.rtol;
  engine.atol = options.atol;  // taken per component below
  engine.h0 = options.h0;
  engine.max_steps = options.max_steps;
  OdeOptions oo = mech::ode_options(engine);
  oo.atol_vec = Eigen::VectorXd::Constant(A, 1e300);  // quadratures: not under error control
  oo.atol_vec.head(n).setConstant(options.atol);
  oo.atol_vec.segment(N, n).setConstant(options.atol);
  oo.rtol_vec = Eigen::VectorXd::Constant(A, options.rtol);
  for (int j = 0; j < m; ++j) {
    const double scale = options.column_scale.size() == m ? options.column_scale[j] : 1.0;
    const double ap = options.control_sensitivities ? options.rtol * scale : 1e300;
    const double av = options.control_sensitivities ? ap * options.velocity_scale : 1e300;
    oo.atol_vec.segment((1 + j) * n, n).setConstant(ap);
    oo.atol_vec.segment(N + (1 + j) * n, n).setConstant(av);
    if (!options.control_sensitivities) {
      oo.rtol_vec.segment((1 + j) * n, n).setConstant(1.0);
      oo.rtol_vec.segment(N + (1 + j) * n, n).setConstant(1.0);
    }
  }
  oo.rtol_vec.tail(A - 2 * N).setConstant(1.0);
  const OdeResult r = ode_integrate(p, t0, ya, t1, oo, options.method);
  res.status = r.status;
  res.t = r.t;
  res.steps = r.steps;
  res.accepted = r.accepted;
  res.rejected = r.rejected;
  res.f_evals = r.f_evals;
  res.used_explicit = r.used_explicit;
  res.used_radau = r.used_radau;
  res.message = r.message;
  if (!aug->failure().empty() && r.status != OdeStatus::success)
    res.message += (res.message.empty() ? "" : "; ") + std::string("the model: ") + aug->failure();
  if (r.y.size() != A) return res;
  res.y.resize(2 * n);
  res.y.head(n) = r.y.head(n);
  res.y.tail(n) = r.y.segment(N, n);
  res.Y.resize(2 * n, m);
  for (int j = 0; j < m; ++j) {
    res.Y.col(j).head(n) = r.y.segment((1 + j) * n, n);
    res.Y.col(j).tail(n) = r.y.segment(N + (1 + j) * n, n);
  }
  const int nq = static_cast<int>(setup.quadrature.size());
  const int nc = static_cast<int>(setup.inverse_mass_quadrature.size());
  const int o = aug->quad_offset();
  res.w = r.y.segment(o, nq);
  res.W.resize(nq, m);
  for (int k = 0; k < nq; ++k)
    for (int j = 0; j < m; ++j) res.W(k, j) = r.y[o + nq + k * m + j];
  res.Cint.resize(nc, nc);
  for (int a = 0; a < nc; ++a)
    for (int b = 0; b < nc; ++b) res.Cint(a, b) = r.y[o + nq + nq * m + a * nc + b];
  res.mean_integrals = r.y.segment(o + nq + nq * m + nc * nc, static_cast<int>(setup.means.size()));
  return res;
}

}  // namespace pcsim::steady
