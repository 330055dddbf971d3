// Event functions for the ODE integrators (issue 12): g(t, y) whose sign changes end an
// integration with status root_found at the earliest root, located on the dense output, in the
// manner of SUNDIALS' IDARootInit / IDAGetRootInfo.
#pragma once

#include <functional>
#include <vector>

namespace pcsim {

/// ng event functions g_i(t, y). After every accepted step the integrator looks for sign
/// changes of each g_i between the start and the end of the step, locates the earliest root on
/// the step's dense output to |t_hi - t_lo| <= time_tolerance, and returns status root_found
/// with t = t_hi (on the far side of the root) and y = the dense output there. Restarting
/// from that (t, y) does not fire the same root again: a g_i that is exactly zero at the start
/// is judged from its value time_tolerance later. Two sign changes of one g_i within one step
/// cancel and are not seen (keep hmax below the shortest interval between such roots).
struct EventFunctions {
  int count = 0;  ///< ng >= 0; 0 = no events

  /// g(t, y) into g[0..count). Return false (or produce a non-finite value, or throw) if g
  /// cannot be evaluated: the integration ends with status callback_error.
  std::function<bool(double t, const double* y, double* g)> g;

  /// Optional, empty or size count: 0 any root, +1 only rising (g_i from < 0 to >= 0),
  /// -1 only falling roots of g_i are events.
  std::vector<int> direction;

  /// Absolute time tolerance of the location; 0 = 100 eps (|t| + |h|) in each step.
  double time_tolerance = 0.0;
};

}  // namespace pcsim
