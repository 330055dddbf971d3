// solve_lcp: loads the Siconos plugin on first use (dlopen) and calls it under a mutex.
#include "lcp/lcp.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

#include "lcp/lcp_plugin.h"

namespace pcsim::lcp {

const char* to_string(LcpStatus status) {
  switch (status) {
#define PCSIM_LCP_NAME(name, text) \
  case LcpStatus::name: return #name;
    PCSIM_LCP_STATUS_TABLE(PCSIM_LCP_NAME)
#undef PCSIM_LCP_NAME
  }
  return "unknown";
}

const char* message(LcpStatus status) {
  switch (status) {
#define PCSIM_LCP_MESSAGE(name, text) \
  case LcpStatus::name: return text;
    PCSIM_LCP_STATUS_TABLE(PCSIM_LCP_MESSAGE)
#undef PCSIM_LCP_MESSAGE
  }
  return "unknown status";
}

const char* lcp_library_name() { return "pcsim_lcp_siconos.so"; }

namespace {

struct Plugin {
  std::mutex call_mutex;            // Siconos is not re-entrant
  std::once_flag once;
  void* handle = nullptr;
  pcsim_lcp_plugin_solve_fn solve = nullptr;
  std::string error;                // why it could not be loaded ("" when loaded)
};

Plugin& plugin() {
  static Plugin p;
  return p;
}

// Where the plugin may be: $PCSIM_LCP_LIBRARY (a file), next to the executable, the install
// layout (<prefix>/bin/pcsim -> <prefix>/lib/pcsim/), and the build tree it was built in.
std::vector<std::string> candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("PCSIM_LCP_LIBRARY"); env && *env) {
    out.push_back(env);
    return out;  // an explicit choice is the only one tried
  }
  char exe[PATH_MAX];
  const ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len > 0) {
    exe[len] = '\0';
    const std::filesystem::path dir = std::filesystem::path(exe).parent_path();
    out.push_back((dir / lcp_library_name()).string());
    out.push_back((dir.parent_path() / "lib" / "pcsim" / lcp_library_name()).string());
  }
#ifdef PCSIM_LCP_PLUGIN_BUILD_PATH
  out.push_back(PCSIM_LCP_PLUGIN_BUILD_PATH);
#endif
  return out;
}

void load(Plugin& p) {
  // Siconos links OpenBLAS: one thread, so results do not depend on the thread count and no
  // thread pool is started for matrices this small. OPENBLAS_CORETYPE stays as the user set it.
  setenv("OPENBLAS_NUM_THREADS", "1", 1);
  std::string tried;
  for (const std::string& path : candidates()) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += (tried.empty() ? "" : "; ") + path + " (no such file)";
      continue;
    }
    void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char* e = dlerror();
      tried += (tried.empty() ? "" : "; ") + path + " (" + (e ? e : "dlopen failed") + ")";
      continue;
    }
    auto abi = reinterpret_cast<pcsim_lcp_plugin_abi_fn>(dlsym(h, "pcsim_lcp_plugin_abi"));
    auto solve = reinterpret_cast<pcsim_lcp_plugin_solve_fn>(dlsym(h, "pcsim_lcp_plugin_solve"));
    if (!abi || !solve || abi() != PCSIM_LCP_PLUGIN_ABI) {
      tried += (tried.empty() ? "" : "; ") + path +
               " (not a pcsim LCP plugin of ABI " + std::to_string(PCSIM_LCP_PLUGIN_ABI) + ")";
      dlclose(h);
      continue;
    }
    p.handle = h;
    p.solve = solve;
    p.error.clear();
    return;
  }
  p.error = std::string("cannot load the LCP library ") + lcp_library_name() +
            " (Siconos numerics, Debian libsiconos-numerics7; set PCSIM_LCP_LIBRARY to its "
            "path): " + (tried.empty() ? std::string("no candidate path") : tried);
}

}  // namespace

bool lcp_library_loaded() {
  Plugin& p = plugin();
  std::lock_guard<std::mutex> lock(p.call_mutex);
  return p.solve != nullptr;
}

LcpResult solve_lcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const LcpOptions& options) {
  LcpResult r;
  const int n = static_cast<int>(q.size());
  if (n == 0 || M.rows() != n || M.cols() != n) {
    r.message = "solve_lcp: M must be n x n and q of size n >= 1";
    return r;
  }
  if (!M.allFinite() || !q.allFinite()) {
    r.message = "solve_lcp: M and q must be finite";
    return r;
  }
  if (!(options.tolerance > 0.0)) {
    r.message = "solve_lcp: the tolerance must be > 0";
    return r;
  }
  Plugin& p = plugin();
  std::lock_guard<std::mutex> lock(p.call_mutex);
  std::call_once(p.once, [&p] { load(p); });
  if (!p.solve) {
    r.status = LcpStatus::library_unavailable;
    r.message = p.error;
    return r;
  }
  const int max_iter = options.max_iterations > 0 ? options.max_iterations
                       : options.solver == LcpSolver::lemke ? 1000 * (n + 1)
                                                            : (n < 30 ? (1 << n) : INT_MAX);
  const Eigen::MatrixXd Mc = M;  // column-major, contiguous
  const Eigen::VectorXd qc = q;
  r.z = Eigen::VectorXd::Zero(n);
  r.w = Eigen::VectorXd::Zero(n);
  char message[512] = {0};
  const int info = p.solve(n, Mc.data(), qc.data(),
                           options.solver == LcpSolver::lemke ? PCSIM_LCP_LEMKE
                                                              : PCSIM_LCP_ENUMERATIVE,
                           options.tolerance, max_iter, r.z.data(), r.w.data(), &r.error,
                           &r.iterations, message, static_cast<int>(sizeof message));
  if (info == 0) {
    // Checked here as well: Siconos's Lemke reports success on some infeasible problems (a
    // ray termination), e.g. M = [-1], q = [-1] comes back with info 0. A point is a solution
    // if z >= 0, w = M z + q >= 0 and z_i w_i = 0, each to tolerance x the problem's scale.
    r.w = Mc * r.z + qc;
    const double scale = 1.0 + std::max(qc.cwiseAbs().maxCoeff(),
                                        (Mc.cwiseAbs() * r.z.cwiseAbs()).maxCoeff());
    const double tol = std::max(options.tolerance, 1e-10) * scale;
    double worst = 0.0;
    for (int i = 0; i < n; ++i)
      worst = std::max({worst, -r.z[i], -r.w[i], std::min(std::abs(r.z[i]), std::abs(r.w[i]))});
    if (!r.z.allFinite() || !(worst <= tol)) {
      r.status = LcpStatus::no_solution;
      r.message = "the Siconos " + std::string(options.solver == LcpSolver::lemke ? "Lemke" : "enumerative") +
                  " solver returned a point that is not a solution (complementarity error " +
                  std::to_string(worst) + "; the LCP may have none)";
    } else {
      r.status = LcpStatus::solved;
    }
  } else {
    r.status = info == -1 ? LcpStatus::bad_input : info == -2 ? LcpStatus::failed
                                                              : LcpStatus::no_solution;
    r.message = message;
  }
  return r;
}

}  // namespace pcsim::lcp
