// Pseudo-arclength continuation of periodic orbits along a parameter: predictor along the
// branch's tangent, corrector by Newton on the shooting residual bordered with the arclength
// condition, so that folds of a nonlinear response are passed, not jumped; Floquet stability
// at every point, folds located where the parameter's direction reverses.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "steady/shooting.hpp"

namespace pcsim::steady {

struct ContinuationOptions {
  double p_start = 0.0, p_stop = 1.0;
  /// The largest parameter step is |p_stop − p_start| / (count − 1); steps shrink where the
  /// orbit changes fast (resonances, folds), measured in the arclength norm below.
  int count = 50;
  int max_points = 5000;
  int corrector_iterations = 10;
  double min_step_fraction = 1e-5;  ///< give up when the step falls below this of the largest
  ShootingOptions shooting;
};

struct BranchPoint {
  double p = 0.0;
  OrbitPoint x;
  Floquet floquet;
  double amplitude = 0.0;   ///< |S (y0 − ȳ)| (the arclength's state scale)
  int iterations = 0;       ///< Newton (corrector) iterations
  double residual = 0.0;    ///< weighted residual at the last linearization
  double tangent_p = 0.0;   ///< dp/ds of the normalized tangent (changes sign at a fold)
  bool fold_before = false; ///< a fold lies between the previous point and this one
  double fold_p = 0.0;      ///< the fold's parameter (the extremum of p along the branch, by a parabola)
};

struct Branch {
  std::vector<BranchPoint> points;
  bool complete = false;    ///< reached p_stop
  std::string message;      ///< why it stopped early
  long integrations = 0, steps = 0;
};

/// Traces the branch from the orbit at p_start (found by Newton shooting from `guess`) towards
/// p_stop. problem_at(p) and derivative_at(p) give the problem and its parameter derivative
/// (they may throw pcsim::InputError). Never throws for numerical trouble: the branch ends
/// with a message.
Branch continue_branch(const std::function<OrbitProblem(double)>& problem_at,
                       const std::function<ParameterDerivative(double)>& derivative_at,
                       const OrbitPoint& guess, const ContinuationOptions& options);

}  // namespace pcsim::steady
