// Eigen's dense decompositions on Eigen::MatrixXd, instantiated once (eigen_instances_*.cpp)
// instead of in every file that uses them.
//
// Why: these class templates are large, and each translation unit that used one compiled it
// again at -O2: BDCSVD alone took 34 s of a file's compile time, JacobiSVD 13 s, and
// cpp/mech/dynamics.cpp (which uses seven of them) 109 s, 46 s with these declarations. An
// explicit instantiation declaration (`extern template`) tells the compiler that the members
// are compiled elsewhere, and they are then not compiled here. `extern template class` covers
// the ordinary members only, not member templates. The LUs' and QRs' compute() is a template
// that copies its argument and calls an ordinary member, which is covered; the eigensolvers',
// LLT's and LDLT's compute() does the work itself, and solve() assigns through the member
// template _solve_impl: those are declared one by one below, for MatrixXd and VectorXd
// arguments (dynamics.cpp 46 -> 30 s, test_modes_sieve.cpp 40 -> 8.5 s). Pass a MatrixXd, not an
// expression, to an eigensolver: an expression type is instantiated again in the calling file.
// Results are unchanged: the same code, compiled with the same flags, called instead of
// instantiated in place (the main job's output and other cases' were compared byte for byte).
//
// The instantiations are in eigen_instances_{svd,qr_lu,eig}.cpp.
//
// pcsim's files include this header instead of <Eigen/Dense> (the installed kernel headers
// excepted). A file that does not include it still works; it compiles its own copy.
#pragma once

#include <Eigen/Dense>

extern template class Eigen::BDCSVD<Eigen::MatrixXd>;
extern template class Eigen::JacobiSVD<Eigen::MatrixXd>;
extern template class Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;
extern template class Eigen::HouseholderQR<Eigen::MatrixXd>;
extern template class Eigen::FullPivLU<Eigen::MatrixXd>;
extern template class Eigen::PartialPivLU<Eigen::MatrixXd>;
extern template class Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>;
extern template class Eigen::EigenSolver<Eigen::MatrixXd>;
extern template class Eigen::LLT<Eigen::MatrixXd>;
extern template class Eigen::LDLT<Eigen::MatrixXd>;
extern template class Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>;

// Member templates, which `extern template class` does not cover: compute() for an argument that
// is a MatrixXd (not an expression, which each file still instantiates for itself). The
// eigensolvers' compute() is where their work is (EigenSolver's 4.2 s of a test file's 28 s).
extern template Eigen::EigenSolver<Eigen::MatrixXd>&
Eigen::EigenSolver<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&, bool);
extern template Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>&
Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&, int);
extern template Eigen::LLT<Eigen::MatrixXd>&
Eigen::LLT<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&);
extern template Eigen::LDLT<Eigen::MatrixXd>&
Eigen::LDLT<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&);

// And solve(b) for b a VectorXd or a MatrixXd, assigned to the same type: the member template
// _solve_impl that the assignment of decomposition.solve(b) calls (CompleteOrthogonalDecomposition's
// took 1.8 s of each file that used it). PartialPivLU's is defined in its class (inline), so it is
// left to each file.
#define PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, D)                                                   \
  EXTERN template void D::_solve_impl(const Eigen::VectorXd&, Eigen::VectorXd&) const;           \
  EXTERN template void D::_solve_impl(const Eigen::MatrixXd&, Eigen::MatrixXd&) const;
#define PCSIM_EIGEN_ALL_SOLVE_INSTANCES(EXTERN)                                                  \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::LLT<Eigen::MatrixXd>)                               \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::LDLT<Eigen::MatrixXd>)                              \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::FullPivLU<Eigen::MatrixXd>)                         \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::HouseholderQR<Eigen::MatrixXd>)                     \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::ColPivHouseholderQR<Eigen::MatrixXd>)               \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>)   \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::SVDBase<Eigen::JacobiSVD<Eigen::MatrixXd>>)         \
  PCSIM_EIGEN_SOLVE_INSTANCES(EXTERN, Eigen::SVDBase<Eigen::BDCSVD<Eigen::MatrixXd>>)
PCSIM_EIGEN_ALL_SOLVE_INSTANCES(extern)
