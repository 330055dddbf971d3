// Linear complementarity problems (w = M z + q, z >= 0, w >= 0, zᵀw = 0) solved by Siconos
// numerics, which pcsim loads on first use: the solver lives in the plugin pcsim_lcp_siconos.so
// (cpp/lcp/siconos_plugin.c), dlopen()ed the first time solve_lcp() is called, after
// OPENBLAS_NUM_THREADS=1 is set (OPENBLAS_CORETYPE stays as the user has it). Siconos links
// OpenBLAS; pcsim itself is pinned to the reference BLAS/LAPACK (CMakeLists.txt), so a run that
// never needs an LCP never loads OpenBLAS, and one that does gets single-threaded,
// deterministic BLAS (tests/lcp/test_lcp_openblas_settings.cpp).
#pragma once

#include <string>

#include "common/eigen_instances.hpp"

namespace pcsim::lcp {

enum class LcpSolver {
  lemke,        ///< lexicographic Lemke (Siconos SICONOS_LCP_LEMKE): complementary pivoting
  enumerative,  ///< enumeration of complementary bases (Siconos SICONOS_LCP_ENUM)
};

/// How an LCP solve ended: the one table (name, message) the enum, to_string() and message()
/// are expanded from.
#define PCSIM_LCP_STATUS_TABLE(X)                                                             \
  /* z, w solve the LCP to the tolerance */                                                   \
  X(solved, "solved")                                                                         \
  /* the solver ended without a solution (message: the solver's code) */                      \
  X(no_solution, "no solution found")                                                         \
  /* the plugin or Siconos could not be loaded (message names them) */                        \
  X(library_unavailable, "the LCP library is not available")                                  \
  /* M not square, sizes differ, n = 0, non-finite entries */                                 \
  X(bad_input, "bad input")                                                                   \
  /* Siconos raised a fatal error (message) */                                                \
  X(failed, "the LCP solver failed")

enum class LcpStatus {
#define PCSIM_LCP_ENUMERATOR(name, message) name,
  PCSIM_LCP_STATUS_TABLE(PCSIM_LCP_ENUMERATOR)
#undef PCSIM_LCP_ENUMERATOR
};
/// The enumerator's name, e.g. "no_solution" ("unknown" outside the table).
const char* to_string(LcpStatus status);
/// The one-line message of the table.
const char* message(LcpStatus status);

struct LcpOptions {
  LcpSolver solver = LcpSolver::lemke;
  double tolerance = 1e-12;  ///< Siconos's complementarity error accepted
  int max_iterations = 0;    ///< pivots or bases; 0 = 1000 (n + 1) for Lemke, 2^n for enum
};

struct LcpResult {
  LcpStatus status = LcpStatus::bad_input;
  Eigen::VectorXd z, w;
  double error = 0.0;   ///< Siconos's complementarity error
  int iterations = 0;   ///< pivots or bases used
  std::string message;  ///< the reason unless solved
};

/// Solves the LCP (M, q) with Siconos. Thread-safe (calls are serialized: Siconos keeps global
/// error state). Never throws.
LcpResult solve_lcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const LcpOptions& options = {});

/// True once the plugin (and with it Siconos and OpenBLAS) has been loaded into this process.
bool lcp_library_loaded();

/// The plugin's file name, for messages ("pcsim_lcp_siconos.so").
const char* lcp_library_name();

}  // namespace pcsim::lcp
