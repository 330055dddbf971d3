// Periodic orbits of a forced mechanical system by Newton shooting on the constraint manifold:
// the unknown is the state at t0 (in coordinates of the manifold's tangent space) and, for each
// slow coordinate, the constant force that holds its period mean; the residual is the state
// after k excitation periods minus the start; the Jacobian is the monodromy matrix from the
// variational equations (exact tangents). Floquet multipliers and stability come with it.
#pragma once

#include <complex>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "mech/model.hpp"
#include "ode/integrate.hpp"

namespace pcsim::steady {

/// The periodic-orbit problem for one parameter set.
struct OrbitProblem {
  /// The model (without holding forces); it must have exact tangents (model files do).
  std::shared_ptr<const mech::Model> model;
  std::vector<int> active;  ///< active constraints (indices into model->constraints())
  double period = std::numeric_limits<double>::quiet_NaN();  ///< excitation period T, s
  int periods = 1;          ///< the orbit's period is periods * T (a subharmonic for > 1)
  double t0 = 0.0;          ///< the phase: the state is sought at t0
  /// Slow coordinates (indices), each held at its period mean `hold[k]` by a constant
  /// generalized force (an unknown of the Newton system; docs/steady.md, "Slow coordinates").
  std::vector<int> slow;
  Eigen::VectorXd hold;
  /// Ω of the scaled state S y = (q, q̇/Ω); 0: 2π/(periods T). Continuation fixes it along a
  /// branch, so that the residual's scaling does not change with the parameter.
  double velocity_scale = 0.0;
};

struct ShootingOptions {
  OdeMethod method = OdeMethod::automatic;  ///< the integrator of the variational equations
  Kernel kernel = Kernel::fortran;
  double rtol = 1e-8, atol = 1e-10;
  long max_steps = 1000000;
  int max_iterations = 30;
  /// Newton stops when the correction, in the integrator's weighted norm (weights
  /// 1/(atol + rtol |y_i|)), is below this: a hundredth of the integration tolerance.
  double newton_tol = 1e-2;
  int max_halvings = 8;     ///< line search: step halvings before giving up
  /// When Newton fails from the guess (far from a strongly nonlinear orbit), integrate the
  /// system over 8, 16, 32, ... orbit periods from the guess (a stable orbit attracts the
  /// transient) and start Newton again from the end, up to this many periods in all (0: never).
  int max_transient_periods = 256;
  double projection_tol = 1e-13;
  bool control_sensitivities = true;  ///< the sensitivities under the integrator's error control
};

/// A point of the unknown space: the state y = (q, q̇) at t0 (on the constraints) and the
/// holding forces H (one per slow coordinate).
struct OrbitPoint {
  Eigen::VectorXd y;
  Eigen::VectorXd H;
};

/// d/dp of the problem for a parameter p, for continuation: the models at p ± h (their
/// difference quotient gives ∂q̈/∂p inside the variational equations, and the manifold's
/// motion by projecting onto each), and the derivatives of the period and the held means.
struct ParameterDerivative {
  std::shared_ptr<const mech::Model> model_plus, model_minus;  ///< inner models at p ± h
  double h = 0.0;
  double dperiod = 0.0;           ///< dT/dp
  Eigen::VectorXd dhold;          ///< d hold / dp (size of slow)
};

/// The shooting residual and its Jacobian at a point, in the coordinates z of the tangent
/// space of the constraint manifold there (an orthonormal basis in the scaled state
/// S y = (q, q̇/Ω), Ω = 2π/(k T)): r = [Bᵀ S (y(t0 + kT) − y(t0)); mean(q_slow) − hold].
struct Linearization {
  bool ok = false;
  std::string message;        ///< why not ok (names the time)
  double t_failed = 0.0;
  Eigen::VectorXd scale;      ///< the diagonal of S (2n)
  Eigen::MatrixXd basis;      ///< B (2n x m): orthonormal, the tangent space in scaled coordinates
  Eigen::VectorXd residual;   ///< r (m + slow)
  Eigen::MatrixXd jacobian;   ///< ∂r/∂(z, H), square
  Eigen::VectorXd dr_dp;      ///< ∂r/∂p when a ParameterDerivative was given
  Eigen::MatrixXd monodromy;  ///< Bᵀ S Φ S⁻¹ B: the monodromy restricted to the manifold
  Eigen::VectorXd y_end;      ///< y(t0 + kT)
  Eigen::VectorXd mean_q;     ///< the period means of every coordinate
  Eigen::VectorXd mean_slow;  ///< the period means of the slow coordinates
  double amplitude = 0.0;     ///< |S (y(t0) − ȳ)|: the orbit's amplitude for a harmonic orbit
  Eigen::MatrixXd C_mean;     ///< period mean of the slow coordinates' constrained inverse mass
  double residual_norm = std::numeric_limits<double>::infinity();  ///< weighted RMS
  double residual_max = std::numeric_limits<double>::infinity();   ///< max |y(kT) − y(0)|
  long steps = 0, f_evals = 0;
  bool used_explicit = false, used_radau = false;
};

struct FloquetMultiplier {
  std::complex<double> value;
  double modulus = 0.0;
  double slow_weight = 0.0;  ///< share of its eigenvector in the slow coordinates (0..1)
  bool slow = false;         ///< one of the slow coordinates' pair (neutral drift)
};

struct Floquet {
  std::vector<FloquetMultiplier> multipliers;  ///< by decreasing modulus
  double max_modulus = 0.0;  ///< the largest |μ| except the slow coordinates' pairs
  bool stable = false;       ///< max_modulus < 1
};

struct NewtonRecord {
  int iteration = 0;
  double residual = 0.0;     ///< weighted RMS norm of the residual at the iterate
  double residual_max = 0.0; ///< max |y(kT) − y(0)|
  double correction = 0.0;   ///< weighted norm of the full Newton correction
  double damping = 1.0;      ///< the step length the line search took
  long steps = 0;            ///< integration steps of the linearization
  /// The residual of the final point only (no linearization there): Newton stopped because the
  /// full step from a point in the quadratic regime left a residual below the tolerance.
  bool check = false;
};

struct OrbitResult {
  bool converged = false;
  std::string message;       ///< why not (iterations, residual reached), or a note
  OrbitPoint point;          ///< the periodic state at t0 and the holding forces
  double residual = 0.0;     ///< weighted residual at the last linearized iterate
  double residual_max = 0.0; ///< its max-norm |y(kT) − y(0)|
  double correction = 0.0;   ///< the last correction's weighted norm
  std::vector<NewtonRecord> history;
  Linearization last;        ///< the linearization at the last iterate (monodromy, basis)
  Floquet floquet;
  Eigen::VectorXd drift_acceleration;  ///< −C̄ H: the slow coordinates' acceleration when let go
  long integrations = 0, steps = 0, f_evals = 0;
  bool used_explicit = false, used_radau = false;
  int transient_periods = 0;  ///< orbit periods integrated before the Newton that converged
};

class Shooter {
 public:
  /// Throws std::invalid_argument for a model without tangents or a bad problem.
  Shooter(OrbitProblem problem, ShootingOptions options);

  const OrbitProblem& problem() const { return problem_; }
  const ShootingOptions& options() const { return options_; }
  int n() const { return n_; }
  double orbit_period() const { return problem_.periods * problem_.period; }

  /// (y, H) with y projected onto the constraints at t0. ok = false (message) if impossible.
  bool project(OrbitPoint& x, std::string& message) const;

  /// The residual and Jacobian at x (and ∂r/∂p when dp is given); with jacobian = false only
  /// the residual (one integration of the orbit without the variational equations).
  Linearization linearize(const OrbitPoint& x, const ParameterDerivative* dp = nullptr,
                          bool jacobian = true) const;

  /// x + α (S⁻¹ B δz, δH), projected onto the constraints.
  bool advance(const OrbitPoint& x, const Linearization& L, const Eigen::VectorXd& delta,
               double alpha, OrbitPoint& out, std::string& message) const;

  /// The weighted norm of a correction δ = (δz, δH) at x: the state change in the
  /// integrator's weights, the holding forces by the drift they cause over the orbit period.
  double correction_norm(const OrbitPoint& x, const Linearization& L,
                         const Eigen::VectorXd& delta) const;

  /// Floquet multipliers of L's monodromy; the slow coordinates' pairs marked.
  Floquet floquet(const Linearization& L) const;

 private:
  Eigen::VectorXd weights(const Eigen::VectorXd& y) const;
  bool tangent_basis(const Eigen::VectorXd& y, const mech::Model& model, Eigen::MatrixXd& B,
                     std::string& message) const;

  OrbitProblem problem_;
  ShootingOptions options_;
  int n_ = 0;
  Eigen::VectorXd scale_;
};

/// Newton shooting from `guess` (projected first): damped Newton with a line search on the
/// weighted residual; if it fails, again from the end of a transient integration (see
/// ShootingOptions::max_transient_periods). Never throws for numerical trouble (converged =
/// false and the message say what was reached); throws std::invalid_argument for a model
/// without tangents.
OrbitResult find_orbit(const OrbitProblem& problem, const OrbitPoint& guess,
                       const ShootingOptions& options);

}  // namespace pcsim::steady
