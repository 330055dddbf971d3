// The variational equations of the ODE form integrated with the trajectory: y = (q, q̇) with
// y' = f(t, y), and sensitivity columns Y' = ∂f/∂y Y + b(t, y) (b: the constrained response to
// constant forces, or a parameter's derivative of f), plus time integrals of coordinates and
// their sensitivities. The Jacobian products come from the engine's exact tangent
// (mech/tangent.hpp), k directions per evaluation. What shooting and continuation integrate.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "mech/dynamics.hpp"
#include "mech/model.hpp"
#include "ode/integrate.hpp"

namespace pcsim::steady {

/// What to integrate besides y = (q, q̇).
struct VariationalSetup {
  const mech::Model* model = nullptr;  ///< must have exact tangents (Model::has_tangents())
  std::vector<int> active;             ///< active constraints (indices into model->constraints())
  /// n x m (or empty: none): column j adds the constrained response to the generalized force
  /// F_j, (0, C F_j), to the derivative of sensitivity column j (C: the constrained inverse
  /// mass matrix). The sensitivity with respect to a constant force F_j h on the system.
  Eigen::MatrixXd forces;
  /// Optional: column `parameter_column` adds (0, ∂q̈/∂p (t, q, q̇)) given by this function
  /// (false: cannot evaluate). The sensitivity with respect to a parameter p.
  std::function<bool(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::VectorXd& dqdd_dp)>
      parameter_term;
  int parameter_column = -1;
  /// Coordinates whose time integral ∫ q_i dt is accumulated, with its sensitivities.
  std::vector<int> quadrature;
  /// Coordinates k whose constrained inverse-mass block is integrated: ∫ C(t)_{ab} dt for a,
  /// b in this list (the drift a slow coordinate's holding force prevents).
  std::vector<int> inverse_mass_quadrature;
  /// Coordinates whose time integral is accumulated without sensitivities (period means).
  std::vector<int> means;
};

struct VariationalOptions {
  OdeMethod method = OdeMethod::automatic;
  Kernel kernel = Kernel::fortran;
  double rtol = 1e-8, atol = 1e-8;  ///< for y = (q, q̇)
  /// The size of each sensitivity column's position part (m entries; empty: all 1) and the
  /// ratio of velocity to position sizes (Ω, 1/s): column j's entries are controlled to
  /// rtol * column_scale[j] (positions) and rtol * column_scale[j] * velocity_scale (velocities)
  /// when control_sensitivities, else they ride on y's steps.
  Eigen::VectorXd column_scale;
  double velocity_scale = 1.0;
  bool control_sensitivities = true;
  double h0 = 0.0;
  long max_steps = 1000000;
};

struct VariationalResult {
  OdeStatus status = OdeStatus::bad_input;
  std::string message;       ///< reason unless success (names the time)
  double t = 0.0;            ///< time reached
  Eigen::VectorXd y;         ///< (q, q̇) at t
  Eigen::MatrixXd Y;         ///< 2n x m sensitivities at t
  Eigen::VectorXd w;         ///< ∫ q_i dt over [t0, t] for the quadrature coordinates
  Eigen::MatrixXd W;         ///< their sensitivities (quadrature count x m)
  Eigen::MatrixXd Cint;      ///< ∫ C_ab dt (inverse_mass_quadrature count, square)
  Eigen::VectorXd mean_integrals;  ///< ∫ q_i dt for the `means` coordinates
  long steps = 0, accepted = 0, rejected = 0, f_evals = 0;
  bool used_explicit = false, used_radau = false;
};

/// Integrates y and its sensitivities from (t0, y0, Y0) to t1. y0 should satisfy the active
/// constraints (no projection is done on the way: over a period the drift stays at the
/// integration tolerance, and the map y0 -> y(t1) stays smooth for Newton). Never throws
/// (model failures come back as status and message).
VariationalResult integrate_variational(const VariationalSetup& setup, double t0, double t1,
                                        const Eigen::VectorXd& y0, const Eigen::MatrixXd& Y0,
                                        const VariationalOptions& options);

}  // namespace pcsim::steady
