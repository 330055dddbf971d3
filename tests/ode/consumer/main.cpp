// Integrates y' = -y to t = 1 with both Radau kernels and solves a 2 x 2 system with Huang,
// through the installed headers and libraries; exits 0 only if the results are right
// (exp(-1) to 1e-7, the linear solution to 1e-12).
#include <cmath>
#include <cstdio>

#include "linalg/huang.hpp"
#include "ode/radau.hpp"

int main() {
  pcsim::OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = -y[0];
    return true;
  };
  int bad = 0;
  for (pcsim::Kernel k : {pcsim::Kernel::fortran, pcsim::Kernel::cpp}) {
    pcsim::RadauOptions o;
    o.kernel = k;
    o.rtol = o.atol = 1e-10;
    const pcsim::RadauResult r = pcsim::radau_integrate(p, 0.0, Eigen::VectorXd::Ones(1), 1.0, o);
    const double err = std::abs(r.y[0] - std::exp(-1.0));
    std::printf("radau %s: %s, y(1) error %.2e\n", pcsim::to_string(k), pcsim::to_string(r.status),
                err);
    if (r.status != pcsim::OdeStatus::success || err > 1e-7) bad = 1;
  }
  // Huang: the minimum-norm solution of x1 + x2 = 2 is (1, 1).
  Eigen::MatrixXd A(1, 2);
  A << 1.0, 1.0;
  const pcsim::HuangResult h = pcsim::huang_solve(A, Eigen::VectorXd::Constant(1, 2.0));
  std::printf("huang: info %d, x = (%g, %g)\n", h.info, h.x[0], h.x[1]);
  if (h.info != 0 || std::abs(h.x[0] - 1.0) > 1e-12 || std::abs(h.x[1] - 1.0) > 1e-12) bad = 1;
  std::printf("status table: %s = \"%s\"\n", pcsim::to_string(pcsim::OdeStatus::non_finite),
              pcsim::meaning(pcsim::OdeStatus::non_finite));
  return bad;
}
