// The linearization of a constrained system about a rest state or a steady motion, reduced to
// the constraint manifold's tangent space, and its eigenvalues and mode shapes (docs: the
// README's "pcsim modes"). Exact derivatives: the ODE form's Jacobian from the model's
// symbolic tangents (mech/tangent.hpp), the constraint rows' derivatives from the same tangents.
//
// For a state y = (q, q̇) the constraint manifold is {Φ_h(q, t) = 0 (holonomic rows),
// g(q, t) q̇ + g0(q, t) = 0 (every active row)}; its tangent space is the null space of
//
//     C = [ g_h                 0 ]      (rows: holonomic positions, then every row's velocity form)
//         [ ∂(g q̇ + g0)/∂q      g ]      (2n columns: δq, δq̇)
//
// computed by an SVD of C with unit rows (a row scaling does not change the null space):
// singular values ≤ rank_tol (1e-10) count as zero. With B an orthonormal basis of null(C),
// A = Bᵀ J B is the constrained system's linearization (J the 2n×2n Jacobian of the ODE
// form); the subspace is invariant under J at a rest state or a relative equilibrium on the
// manifold, and ‖J B − B A‖ / ‖J‖ is reported as the check.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/model.hpp"

namespace pcsim::modes {

struct LinearizeInput {
  const mech::Model* model = nullptr;
  std::vector<int> active;     ///< active constraints (indices into model->constraints())
  Eigen::VectorXd q, qd;       ///< the reference state
  /// The times at which the model is evaluated; the Jacobian (and the forces of the rest check)
  /// is their mean. One time: the excitation held at that instant. Several (one period,
  /// equally spaced): the excitation's periodic part averaged out (excitation "off").
  std::vector<double> times = {0.0};
  std::vector<int> cyclic;     ///< coordinates that move at constant rates (steady motion)
  /// Constant generalized forces added to the rest check (the holding forces of slow
  /// coordinates held by the static equilibrium); empty or size n.
  Eigen::VectorXd extra_force;
  double rank_tol = 1e-10;     ///< relative singular value below which a row of C is dependent
  double rest_tol = 1e-8;      ///< relative force imbalance accepted as rest
};

struct Mode {
  std::complex<double> lambda;    ///< σ + iω (the member of a pair with ω > 0)
  bool pair = false;              ///< a complex pair σ ± iω (this is the + member)
  std::string kind;               ///< oscillatory, real, rigid-body, cyclic
  double natural_frequency = 0;   ///< |λ|, rad/s
  double damped_frequency = 0;    ///< |Im λ|, rad/s
  double damping_ratio = 0;       ///< −σ/|λ| (NaN for a zero eigenvalue)
  Eigen::VectorXcd shape;         ///< over the coordinates (δq), largest component 1
  std::vector<int> dominant;      ///< coordinates with |shape| ≥ 0.1, largest first (≤ 4)
};

struct Linearization {
  int n = 0;
  int holonomic_rows = 0, velocity_rows = 0;  ///< rows of C
  int rank = 0;                               ///< rank of C
  int dimension = 0;                          ///< of the tangent space: 2n − rank
  double rank_gap_below = 0, rank_gap_above = 0;  ///< the last kept and first dropped singular values
  Eigen::MatrixXd J, B, A;
  double invariance = 0;                      ///< ‖J B − B A‖_F / max(‖J‖_F, 1)
  // The rest check.
  Eigen::VectorXd qdd;                        ///< accelerations at the reference (mean forces)
  Eigen::VectorXd imbalance;                  ///< M q̈: the generalized force left unbalanced
  double residual = 0, force_scale = 0;       ///< max |imbalance|, the largest force at rest
  std::vector<int> moving;                    ///< coordinates with an imbalance above rest_tol
  std::vector<int> moving_velocity;           ///< non-cyclic coordinates with q̇ ≠ 0
  std::vector<int> cyclic_in_equations;       ///< cyclic coordinates the equations depend on
  // The eigen-analysis.
  Eigen::VectorXcd eigenvalues;               ///< all `dimension` of them
  Eigen::MatrixXcd eigenvectors;              ///< their eigenvectors in (δq, δq̇) (2n rows), unit length
  std::vector<Mode> modes;                    ///< pairs once, sorted by natural frequency
  double zero_tol = 0;                        ///< |λ| below which an eigenvalue counts as zero
  bool stable = false;                        ///< every Re λ < zero_tol (zero modes marginal)
  // Undamped: the velocity tangent space's basis N (null of all rows g), the reduced mass and
  // stiffness with the velocity-dependent terms (damping, gyroscopic) dropped.
  Eigen::MatrixXd Mr, Kr;
  std::vector<double> omega2;                 ///< eigenvalues of Mr⁻¹ Kr, ascending (ω²; < 0: unstable)
};

/// Linearizes and analyses. Throws pcsim::NumericalError (exit 3) when the model cannot be
/// evaluated there (a singular mass matrix, a singular reaction system) or the reduced mass
/// matrix is singular; the rest check and the cyclic check are reported in the result, not
/// thrown (the caller decides; see rest_problem()).
Linearization linearize(const LinearizeInput& in);

/// "" if the reference is a rest state (or relative equilibrium) with its cyclic coordinates
/// absent from the equations; otherwise the reason, naming the residual and the coordinates.
std::string rest_problem(const Linearization& L, const std::vector<std::string>& coordinates,
                         const std::vector<int>& cyclic);

}  // namespace pcsim::modes
