// The Fortran test driver (tests/linalg/huang_driver.f90, which calls PCHUAN/PCHNUL directly)
// and C++ give the same results on the same inputs: the driver's file holds the inputs and
// its results; here the same inputs go through the public API, once through the bridge and
// once through the C++ port. CTest runs the driver first (fixture huang_driver_results).
#define BOOST_TEST_MODULE huang_driver
#include <boost/test/unit_test.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../support/build_tree.hpp"
#include "huang_test_util.hpp"
#include "linalg/huang.hpp"

using namespace pcsim;
using namespace pcsim::test;

namespace {

// Written by the huang_driver test (a fixture of this one) into the build tree.
std::string results_file() {
  return (pcsim_test::binary_dir() / "huang_driver_results.txt").string();
}

// Reads k reals; an empty array is written as a single "-".
std::vector<double> read_reals(std::istream& in, long k) {
  std::vector<double> v(static_cast<std::size_t>(k));
  if (k == 0) {
    std::string dash;
    in >> dash;
    return v;
  }
  for (double& e : v) in >> e;
  return v;
}

Eigen::MatrixXd as_matrix(const std::vector<double>& v, long rows, long cols) {
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), rows, cols);
}

}  // namespace

BOOST_AUTO_TEST_CASE(cpp_through_bridge_and_port_match_the_fortran_driver) {
  // 1e-13 relative: the cross-language contract (the arithmetic is the same, and the
  // driver prints 17 significant digits, so the inputs are read back exactly).
  const std::string results = results_file();
  std::ifstream in(results);
  BOOST_TEST_REQUIRE(in.good(), "missing " << results << ": run the huang_driver test first "
                                           "(ctest -R huang runs it as a fixture)");
  int ncase = 0;
  in >> ncase;
  BOOST_TEST_REQUIRE(ncase >= 8);
  int inconsistent = 0, deficient = 0;
  for (int c = 0; c < ncase; ++c) {
    int meth = 0, m = 0, n = 0, info = 0, rank = 0;
    in >> meth >> m >> n >> info >> rank;
    BOOST_TEST_REQUIRE(in.good());
    const Eigen::MatrixXd A = as_matrix(read_reals(in, long(m) * n), m, n);
    const Eigen::VectorXd b = as_matrix(read_reals(in, m), m, 1);
    const Eigen::VectorXd x1 = as_matrix(read_reals(in, n), n, 1);
    std::vector<int> idep(static_cast<std::size_t>(m));
    for (int& e : idep) in >> e;
    const Eigen::VectorXd x = as_matrix(read_reals(in, n), n, 1);
    const Eigen::MatrixXd H = as_matrix(read_reals(in, long(n) * n), n, n);
    int nulinfo = 0;
    in >> nulinfo;
    const int dcols = n - rank;  // the driver writes D(:, 1:n-rank), zeros when not formed
    const Eigen::MatrixXd D = as_matrix(read_reals(in, long(n) * dcols), n, dcols);
    BOOST_TEST_REQUIRE(!in.fail());

    for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
      HuangOptions o;
      o.kernel = k;
      o.reproject = meth != 2;
      const HuangResult h = huang_solve(A, b, x1, o);
      BOOST_TEST(h.info == info, "case " << c);
      BOOST_TEST(h.rank == rank, "case " << c);
      for (int i = 0; i < m; ++i)
        BOOST_TEST(h.row_dependent[static_cast<std::size_t>(i)] == (idep[static_cast<std::size_t>(i)] > 0));
      BOOST_TEST(rel_diff(h.x, x) <= 1e-13, "case " << c);
      BOOST_TEST(rel_diff(h.H, H) <= 1e-13, "case " << c);
      if (info == 0) {
        const NullBasisResult nb = huang_null_basis(h.H, h.rank, o);
        BOOST_TEST(nb.info == nulinfo);
        BOOST_TEST(rel_diff(nb.D, D) <= 1e-13, "case " << c);
      }
    }
    inconsistent += info > 0 ? 1 : 0;
    deficient += rank < std::min(m, n) ? 1 : 0;
  }
  BOOST_TEST(inconsistent >= 1);
  BOOST_TEST(deficient >= 2);
}
