// The explicit pair against a published reference: the Arenstorf orbit (Hairer, Norsett &
// Wanner I, II.0) returns to its initial value after the published period T. The orbit passes
// close to the moon, which amplifies the local errors by about 1e4 over a period, so the error
// at T is bounded by 2e4 tol (observed 0.7e4 .. 0.9e4 tol for tol = 1e-6 .. 1e-10, and
// 800 tol at 1e-12; roundoff dominates below 1e-12).
#define BOOST_TEST_MODULE explicit_rk_reference
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "explicit_problems.hpp"

using namespace pcsim;
using namespace pcsim::explicit_problems;

BOOST_AUTO_TEST_CASE(arenstorf_orbit_closes_after_one_period) {
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    for (double tol : {1e-6, 1e-8, 1e-10, 1e-12}) {
      ExplicitRkOptions o;
      o.kernel = k;
      o.rtol = o.atol = tol;
      const ExplicitRkResult r = explicit_rk_integrate(arenstorf_problem(), 0.0, arenstorf_y0(),
                                                       kArenstorfPeriod, o);
      BOOST_REQUIRE(r.status == OdeStatus::success);
      const double err = (r.y - arenstorf_y0()).lpNorm<Eigen::Infinity>();
      BOOST_TEST_MESSAGE(to_string(k) << " tol " << tol << ": |y(T) - y(0)| = " << err << " ("
                                      << err / tol << " tol), " << r.stats.f_evals
                                      << " f-evaluations, " << r.stats.accepted << " steps");
      BOOST_TEST(err < 2e4 * tol, "tol " << tol << ": error " << err);
    }
  }
}

BOOST_AUTO_TEST_CASE(oscillators_with_the_sieve_eigenvalues_match_the_closed_form) {
  // Error relative to max(|y|, 1e-3) (the displacements are ~1e-3): below 10 tol.
  for (double tol : {1e-6, 1e-9}) {
    ExplicitRkOptions o;
    o.rtol = o.atol = tol;
    const ExplicitRkResult r = explicit_rk_integrate(oscillators_problem(), 0.0,
                                                     Eigen::VectorXd::Zero(8), 1.0, o);
    BOOST_REQUIRE(r.status == OdeStatus::success);
    const double err = scaled_error(r.y, oscillators_solution(1.0), 1e-3);
    BOOST_TEST_MESSAGE("oscillators tol " << tol << ": error " << err << ", " << r.stats.f_evals
                                          << " f-evaluations");
    BOOST_TEST(err < 10.0 * tol);
  }
}
