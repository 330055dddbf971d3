// The reduced pendulums of the rolling tests (a wheel on a sphere, a disk on a circle: one
// conservative degree of freedom th_dd = acc(th)), integrated by classical RK4.
#pragma once

namespace pcsim::testing {

/// One RK4 step of length h of th_dd = acc(th).
template <class Acc>
void rk4_step(double& th, double& thd, double h, const Acc& acc) {
  const double k1 = thd, l1 = acc(th), k2 = thd + h / 2 * l1, l2 = acc(th + h / 2 * k1),
               k3 = thd + h / 2 * l2, l3 = acc(th + h / 2 * k2), k4 = thd + h * l3, l4 = acc(th + h * k3);
  th += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  thd += h / 6 * (l1 + 2 * l2 + 2 * l3 + l4);
}

}  // namespace pcsim::testing
