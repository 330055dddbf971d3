// Coordinate projection onto the active constraints: the minimum-norm (Huang) corrections of q
// (Newton on the holonomic Φ) and of q̇ (g q̇ + g0 = 0), used for consistent initial values and
// for drift control after accepted steps.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "common/kernel.hpp"
#include "mech/model.hpp"
#include "mech/simulation.hpp"

namespace pcsim::mech {

struct ProjectionWork {
  Eigen::MatrixXd g;
  Eigen::VectorXd g0, gamma;
};

/// Projects (q, qd) in place. tol: relative Newton tolerance for the position part. On return
/// dq, dv are the 2-norms of the total corrections. Returns the issue (message in *message).
ModelIssue project_state(const Model& model, const std::vector<int>& active, double t,
                         Eigen::VectorXd& q, Eigen::VectorXd& qd, Kernel kernel, double tol,
                         double& dq, double& dv, std::string& message, ProjectionWork& work);

/// Resolves constraint names to indices into model.constraints(); returns the issue.
ModelIssue resolve_constraints(const Model& model, const std::vector<std::string>& names,
                               std::vector<int>& active, std::string& message);

}  // namespace pcsim::mech
