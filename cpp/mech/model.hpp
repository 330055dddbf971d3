// The model author's interface: a mechanical system as a plain struct with templated scalar
// functions, turned by make_model() into an immutable, type-erased pcsim::mech::Model whose
// derivatives (M, h, g, g0, ġq̇ + ġ0) come from automatic differentiation.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/eigen_instances.hpp"

namespace pcsim::mech {

template <class S> using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

enum class ConstraintKind {
  holonomic,  ///< Φ_i(q, t) = 0; the engine derives g_i = ∂Φ_i/∂q, g0_i = ∂Φ_i/∂t
  velocity,   ///< given directly as a row of g(q, t) q̇ + g0(q, t) = 0 (paper's form)
};

/// Contact attributes of a constraint (issue 12), used by the switching simulation
/// (mech/contacts/switching.hpp) and ignored by everything else: a constraint is unilateral (its gap
/// gap_sign·Φ must stay >= 0 and its normal force gap_sign·λ, with R = gᵀλ, is >= 0 while it
/// is closed), a friction constraint attached to a unilateral one (its row g q̇ + g0 is the
/// sliding velocity, its multiplier λ the friction force, Coulomb |λ| <= μ_s λ_n), or neither.
struct ContactInfo {
  bool unilateral = false;
  int gap_sign = 1;            ///< +1: the gap is Φ; −1: the gap is −Φ
  double restitution = 0.0;    ///< Newton's e_n in [0, 1]
  int friction_of = -1;        ///< a friction constraint: index of its unilateral constraint
  /// A rough row of that contact (no μ): imposed, like a bilateral row, while the contact is
  /// closed, released in its flights; it never slips (the perfectly rough limit μ → ∞: a wheel
  /// that rolls without slip while it touches and flies when it lifts off). Velocity form.
  bool rough = false;
  double mu_static = 0.0;      ///< Coulomb's static coefficient μ_s >= μ_k
  double mu_kinetic = 0.0;     ///< Coulomb's kinetic coefficient μ_k >= 0
  /// A row of a contact's (Coulomb friction or rough): not bilateral.
  bool is_friction() const { return friction_of >= 0; }
  bool is_coulomb() const { return friction_of >= 0 && !rough; }
};

struct ConstraintInfo {
  std::string name;
  ConstraintKind kind = ConstraintKind::holonomic;
  /// Promise: the row g_i does not depend on q or t (e.g. u = u0, s − rφ = c). When every
  /// active row is constant, the engine computes the null-space basis D (Huang kernel) once per
  /// run instead of once per right-hand side. The engine verifies the promise at the initial
  /// state and at a perturbed state before integrating.
  bool constant_row = false;
  /// Whether a case imposes the constraint unless it says otherwise (a model may offer
  /// constraints that are off by default, e.g. a variant or a deliberate redundancy).
  bool active_by_default = true;
  /// Unilateral contact and friction (issue 12); a plain bilateral constraint by default.
  ContactInfo contact = {};
};

// ---- What a model author writes ---------------------------------------------------------------
//
//   struct MyModel {
//     // required
//     std::string name() const;
//     std::vector<std::string> coordinates() const;                        // n names
//     template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const;
//     template <class S> S potential_energy(const VecX<S>& q, const S& t) const;
//     // optional (detected; absent means "none")
//     static constexpr int kCoordinates = 6;   // n at compile time: fixed-size AD, ~2x faster
//     template <class S> S dissipation(const VecX<S>& q, const VecX<S>& qd, const S& t) const;
//                                                            // Rayleigh F: Q gets −∂F/∂q̇
//     template <class S> VecX<S> applied_forces(const VecX<S>& q, const VecX<S>& qd,
//                                               const S& t) const;      // extra Q (size n)
//     std::vector<ConstraintInfo> constraints() const;     // every constraint it offers
//     template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const;  // Φ_i
//     template <class S> void velocity_form(int i, const VecX<S>& q, const S& t,
//                                           VecX<S>& g_row, S& g0) const;  // row i (size n)
//     std::vector<std::string> derived_names() const;      // e.g. {"fstar"}
//     void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
//                  const Eigen::VectorXd& R, Eigen::VectorXd& out) const;  // out sized by you
//   };
//
// i is the index into constraints(); holonomic() is called only for holonomic ones and
// velocity_form() only for velocity ones. Q = −∂V/∂q − ∂F/∂q̇ + applied_forces.
// T must be quadratic in q̇ (M = ∂²T/∂q̇² is then independent of q̇). S is double or an
// Eigen AutoDiffScalar: write the functions with `using std::sin; sin(x)` style (ADL), no
// branches on derivative values, and no static/global mutable state. Write constants as plain
// doubles (0.5 * m * v) rather than S(0.5): without kCoordinates, an S(c) with an empty
// derivative vector that meets a compound AD expression trips an Eigen size assertion.
// A model struct may have at most kMaxCoordinates coordinates (the AD types are small-buffer
// types); models from model files (expression tapes) have no such limit.

inline constexpr int kMaxCoordinates = 16;

/// An immutable mechanical system, derived by automatic differentiation from a model struct.
/// Thread-safe: every member is const and uses no shared mutable state.
class Model {
 public:
  virtual ~Model() = default;

  const std::string& name() const { return name_; }
  int n() const { return static_cast<int>(coordinates_.size()); }
  const std::vector<std::string>& coordinates() const { return coordinates_; }
  const std::vector<ConstraintInfo>& constraints() const { return constraints_; }
  const std::vector<std::string>& derived_names() const { return derived_names_; }
  /// Index of the constraint with this name in constraints(), or -1.
  int constraint_index(const std::string& constraint_name) const;

  /// M = ∂²T/∂q̇² (n x n) and h (n): M q̈ + h = d/dt(∂T/∂q̇) − ∂T/∂q, i.e.
  /// h = (∂²T/∂q̇∂q) q̇ + ∂²T/∂q̇∂t − ∂T/∂q. M and h must be sized n x n and n.
  virtual void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             Eigen::MatrixXd& M, Eigen::VectorXd& h) const = 0;

  /// Q = −∂V/∂q − ∂F/∂q̇ + applied_forces (n), Q sized n.
  virtual void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                      Eigen::VectorXd& Q) const = 0;

  /// Rows of the active constraints (indices into constraints()): g (s x n), g0 (s) with
  /// g q̇ + g0 = 0, and gamma = ġ q̇ + ġ0 (s), the acceleration-level term: the constraint
  /// differentiated once more in time reads g q̈ + gamma = 0. Outputs must be sized s x n, s, s.
  virtual void constraint_rows(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& qd, Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                               Eigen::VectorXd& gamma) const = 0;

  /// Φ_i(q, t) of constraint i (holonomic only; NaN for a velocity-form constraint).
  virtual double position_residual(int i, double t, const Eigen::VectorXd& q) const = 0;
  /// out[k] = position_residual(rows[k], t, q) for every k, the same numbers in one call (a
  /// model may share the work of setting up the state: ExpressionModel copies q once, not once
  /// per row, which made residual sweeps O(s n)).
  virtual void position_residuals(const std::vector<int>& rows, double t, const Eigen::VectorXd& q,
                                  double* out) const {
    for (std::size_t k = 0; k < rows.size(); ++k) out[k] = position_residual(rows[k], t, q);
  }

  /// The model's derived quantities (size derived_names().size()) at a state with
  /// accelerations qdd and reactions R.
  virtual void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                       const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
                       Eigen::VectorXd& out) const = 0;
  /// The same, with the multipliers of the imposed constraints: lambda[k] belongs to
  /// constraint imposed[k] (R = gᵀ λ); the others' multipliers are NaN. Models whose outputs
  /// use multipliers (model files: lambda_<constraint>) override it; the default ignores them.
  virtual void derived_with_multipliers(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                        const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
                                        const std::vector<int>& imposed, const Eigen::VectorXd& lambda,
                                        Eigen::VectorXd& out) const {
    (void)imposed;
    (void)lambda;
    derived(t, q, qd, qdd, R, out);
  }

  // ---- sparse structure (optional, issue 23) ----------------------------------------------
  // A large model (absolute coordinates: one small block of M per body, a few coordinates per
  // constraint row) can deliver M and g as the values of a fixed sparsity pattern instead of
  // dense n x n and s x n matrices, so that the engine's sparse path (mech/sparse_compat.hpp)
  // does no work proportional to n² per evaluation. The pattern is structural: it holds every
  // entry that can be nonzero at any state and parameter set of this instance (an entry of the
  // pattern may be zero at a state). The dense calls above stay the contract every model keeps;
  // the sparse calls give the same numbers (the dense M and g are zero outside the pattern).
  // Models from model files have it (their tape knows the entries); make_model's do not.

  /// The pattern: `mass` lists the entries (i, j), i <= j, of M's upper triangle that may be
  /// nonzero (each once; M is symmetric); `rows[c]` the columns (ascending) where row g_c of
  /// constraint c (an index into constraints()) may be nonzero.
  struct SparsePattern {
    std::vector<std::pair<int, int>> mass;
    std::vector<std::vector<int>> rows;
  };
  /// True if sparse_pattern() and the two *_sparse calls below are available.
  virtual bool has_sparse_structure() const { return false; }
  /// The fixed pattern (the same object for the model's lifetime).
  virtual const SparsePattern& sparse_pattern() const {
    throw std::logic_error("model '" + name_ + "' has no sparse structure");
  }
  /// M's values in the order of sparse_pattern().mass (mass_values: that many doubles) and h
  /// (sized n), as kinetic_terms gives them.
  virtual void kinetic_terms_sparse(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                    double* mass_values, Eigen::VectorXd& h) const {
    throw std::logic_error("model '" + name_ + "' has no sparse structure");
  }
  /// The rows of the active constraints as constraint_rows gives them, g as values: row r's
  /// entries in the order of sparse_pattern().rows[active[r]], rows one after the other
  /// (row_values: the sum of those sizes); g0, gamma sized s.
  virtual void constraint_rows_sparse(const std::vector<int>& active, double t,
                                      const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                      double* row_values, Eigen::VectorXd& g0,
                                      Eigen::VectorXd& gamma) const {
    throw std::logic_error("model '" + name_ + "' has no sparse structure");
  }

  // ---- exact tangents (optional) ------------------------------------------------------------
  // Forward-mode directional derivatives of M, h, Q and the constraint rows with respect to
  // (q, q̇, t), k directions at once: V is (2n + 1) x k, each column a direction (δq, δq̇, δt);
  // the outputs are the values (as above) and, per direction j, dM[j] (n x n), dh.col(j),
  // dQ.col(j), dg[j] (s x n), dg0.col(j), dgamma.col(j). Models from model files have them
  // (exact, from the tape); the C++ AD models (make_model) do not: has_tangents() is false and
  // the calls throw std::logic_error. The engine's exact Jacobian (mech/tangent.hpp) needs them.

  /// True if the three *_tangent calls below are available.
  virtual bool has_tangents() const { return false; }
  virtual void kinetic_terms_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                     const Eigen::MatrixXd& V, Eigen::MatrixXd& M,
                                     Eigen::VectorXd& h, std::vector<Eigen::MatrixXd>& dM,
                                     Eigen::MatrixXd& dh) const {
    throw std::logic_error("model '" + name_ + "' has no exact tangents");
  }
  virtual void forces_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                              const Eigen::MatrixXd& V, Eigen::VectorXd& Q,
                              Eigen::MatrixXd& dQ) const {
    throw std::logic_error("model '" + name_ + "' has no exact tangents");
  }
  virtual void constraint_rows_tangent(const std::vector<int>& active, double t,
                                       const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                       const Eigen::MatrixXd& V, Eigen::MatrixXd& g,
                                       Eigen::VectorXd& g0, Eigen::VectorXd& gamma,
                                       std::vector<Eigen::MatrixXd>& dg, Eigen::MatrixXd& dg0,
                                       Eigen::MatrixXd& dgamma) const {
    throw std::logic_error("model '" + name_ + "' has no exact tangents");
  }

 protected:
  std::string name_;
  std::vector<std::string> coordinates_;
  std::vector<ConstraintInfo> constraints_;
  std::vector<std::string> derived_names_;
};

/// Wraps a model struct (see above) into an immutable Model. The struct is copied in.
/// Throws std::invalid_argument (a programming error in the C++ model, not the user's input) if
/// the model has no coordinates, more than kMaxCoordinates, or a kCoordinates that disagrees.
template <class Impl> std::shared_ptr<const Model> make_model(Impl impl);

}  // namespace pcsim::mech

#include "mech/detail/autodiff_model.hpp"  // the template definition of make_model
