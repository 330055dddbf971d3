// Accuracy and speed of the Huang solver: plain against modified Huang (re-projection) on
// Hilbert and Vandermonde systems, with LAPACK's dgelsd as the reference, then timing ratios
// Fortran kernel : C++ port : dgelsd measured in this process. Prints Markdown tables.
//
//   build-*/bench_huang_accuracy            (all tables)
//   build-*/bench_huang_accuracy --quick    (fewer timing repetitions)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "../tests/linalg/huang_test_util.hpp"
#include "linalg/huang.hpp"

using namespace pcsim;
using namespace pcsim::test;

namespace {

struct Row {
  int rank = 0;
  double err_lapack = 0.0;  // ||x - x_dgelsd|| / ||x_dgelsd||
  double err_true = 0.0;    // ||x - x_true|| / ||x_true||
  double resid = 0.0;       // ||A x - b|| / (||A|| ||x|| eps)
  double idem = 0.0;        // ||H^2 - H||_F, H of the leading n-1 rows (rank-1 projector)
  double annih = 0.0;       // ||A' H||_F / ||A'||_F, A' = those n-1 rows
};

// "r" for a solved system of rank r, "inc@i" when row i was reported inconsistent.
std::string rank_text(const Row& r) {
  return r.rank >= 0 ? std::to_string(r.rank) : "inc@" + std::to_string(-r.rank);
}

Row huang_row(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& xt,
              const Eigen::VectorXd& xl, bool reproject) {
  HuangOptions o;
  o.reproject = reproject;
  const HuangResult h = huang_solve(A, b, o);
  Row r;
  r.rank = h.info == 0 ? h.rank : -h.info;
  r.err_lapack = rel_diff(h.x, xl);
  r.err_true = rel_diff(h.x, xt);
  r.resid = (A * h.x - b).norm() / (A.norm() * h.x.norm() * kEps);
  // For a square full-rank A the final H is exactly 0, so the projector's quality is judged
  // on the leading n-1 rows, whose null space is one-dimensional.
  const Eigen::MatrixXd A1 = A.topRows(A.cols() - 1);
  const HuangResult h1 = huang_solve(A1, A1 * xt, o);
  r.idem = (h1.H * h1.H - h1.H).norm();
  r.annih = (A1 * h1.H).norm() / A1.norm();
  return r;
}

void accuracy_table(const char* title, const std::vector<std::pair<std::string, Eigen::MatrixXd>>& mats) {
  std::printf("\n%s\n\n", title);
  std::printf("| matrix | kappa | dgelsd rank | dgelsd err | dgelsd resid | plain rank | plain err "
              "| plain resid | plain idem | plain AH | modified rank | modified err | modified resid "
              "| modified idem | modified AH |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [name, A] : mats) {
    const Eigen::VectorXd xt = Eigen::VectorXd::Ones(A.cols());
    const Eigen::VectorXd b = A * xt;
    const GelsdResult g = gelsd(A, b, -1.0);  // rcond < 0: machine precision
    const double kap = g.s(0) / g.s(g.s.size() - 1);
    const double gres = (A * g.x - b).norm() / (A.norm() * g.x.norm() * kEps);
    const Row p = huang_row(A, b, xt, g.x, false);
    const Row m = huang_row(A, b, xt, g.x, true);
    std::printf("| %s | %.1e | %d | %.1e | %.2g | %s | %.1e | %.2g | %.1e | %.1e | %s | %.1e | %.2g "
                "| %.1e | %.1e |\n",
                name.c_str(), kap, g.rank, rel_diff(g.x, xt), gres, rank_text(p).c_str(),
                p.err_lapack, p.resid, p.idem, p.annih, rank_text(m).c_str(), m.err_lapack,
                m.resid, m.idem, m.annih);
  }
}

// Seconds per call of each of the functions fs: each gets a repetition count that makes one
// batch last at least `min_seconds`; then 9 rounds run one batch of every function in turn and
// the best batch of each is kept. Interleaving and the minimum make the ratios robust on a
// shared machine (every variant sees the same disturbances).
std::vector<double> seconds_per_call(const std::vector<std::function<void()>>& fs,
                                     double min_seconds) {
  using clock = std::chrono::steady_clock;
  auto batch = [](const std::function<void()>& f, long reps) {
    const auto t0 = clock::now();
    for (long i = 0; i < reps; ++i) f();
    return std::chrono::duration<double>(clock::now() - t0).count();
  };
  std::vector<long> reps(fs.size(), 1);
  std::vector<double> best(fs.size(), 1e300);
  for (std::size_t k = 0; k < fs.size(); ++k)
    while (batch(fs[k], reps[k]) < min_seconds) reps[k] *= 2;
  for (int round = 0; round < 9; ++round)
    for (std::size_t k = 0; k < fs.size(); ++k)
      best[k] = std::min(best[k], batch(fs[k], reps[k]) / static_cast<double>(reps[k]));
  return best;
}

volatile double g_sink = 0.0;  // keeps the optimizer from dropping the timed work

void timing_table(double min_seconds) {
  std::printf("\nTiming (seconds per solve; ratios against dgelsd measured in this run)\n\n");
  std::printf("| system | dgelsd [s] | Fortran / dgelsd | C++ port / dgelsd | C++ / Fortran "
              "| Fortran solve+basis / dgelsd |\n");
  std::printf("|---|---|---|---|---|---|\n");
  std::mt19937 rng(42);
  for (auto [m, n] : {std::pair{4, 6}, std::pair{6, 6}, std::pair{50, 50}}) {
    const TestSystem s = make_system(rng, n, random_pattern(rng, m, std::min(m, n)), 0.0, 0.0);
    // dgelsd with preallocated workspace (it overwrites A and b, so copy them in each call).
    const int lda = m, ldb = std::max(m, n), nrhs = 1;
    const double rcond = -1.0;
    Eigen::MatrixXd a = s.A;
    Eigen::VectorXd bb = Eigen::VectorXd::Zero(ldb), sv(std::min(m, n));
    double wq = 0.0;
    int iwq = 0, lwork = -1, rank = 0, info = 0;
    dgelsd_(&m, &n, &nrhs, a.data(), &lda, bb.data(), &ldb, sv.data(), &rcond, &rank, &wq,
            &lwork, &iwq, &info);
    lwork = static_cast<int>(wq) + 1;
    std::vector<double> work(static_cast<std::size_t>(lwork));
    std::vector<int> iwork(static_cast<std::size_t>(std::max(1, iwq)));
    HuangWorkspace ws;
    HuangResult res;
    NullBasisResult nb;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    HuangOptions of, oc;
    oc.kernel = Kernel::cpp;
    const std::vector<double> t = seconds_per_call(
        {[&] {
           a = s.A;
           bb.head(m) = s.b;
           dgelsd_(&m, &n, &nrhs, a.data(), &lda, bb.data(), &ldb, sv.data(), &rcond, &rank,
                   work.data(), &lwork, iwork.data(), &info);
           g_sink = g_sink + bb(0);
         },
         [&] {
           huang_solve(s.A, s.b, zero, of, ws, res);
           g_sink = g_sink + res.x(0);
         },
         [&] {
           huang_solve(s.A, s.b, zero, oc, ws, res);
           g_sink = g_sink + res.x(0);
         },
         [&] {
           huang_solve(s.A, s.b, zero, of, ws, res);
           huang_null_basis(res.H, res.rank, of, ws, nb);
           g_sink = g_sink + res.x(0) + (nb.D.size() > 0 ? nb.D(0, 0) : 0.0);
         }},
        min_seconds);
    const double t_lapack = t[0], t_basis = t[3];
    const double tk[2] = {t[1], t[2]};
    std::printf("| %d x %d | %.2e | %.2f | %.2f | %.2f | %.2f |\n", m, n, t_lapack,
                tk[0] / t_lapack, tk[1] / t_lapack, tk[1] / tk[0], t_basis / t_lapack);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::vector<std::pair<std::string, Eigen::MatrixXd>> hilb, vand;
  for (int n = 4; n <= 12; ++n) hilb.emplace_back("Hilbert " + std::to_string(n), hilbert(n));
  for (int n = 4; n <= 12; n += 2) {
    vand.emplace_back("Vandermonde " + std::to_string(n) + "x" + std::to_string(n),
                      vandermonde(n, n));
    vand.emplace_back("Vandermonde " + std::to_string(2 * n) + "x" + std::to_string(n),
                      vandermonde(2 * n, n));
  }
  std::printf("Huang accuracy: b = A * ones, default tolerance, x1 = 0. dgelsd err = ||x - ones|| / "
              "||ones||; plain/modified err = ||x - x_dgelsd|| / ||x_dgelsd||; resid = ||Ax-b|| / "
              "(||A|| ||x|| eps); idem = ||H^2-H||_F and AH = ||A'H||_F / ||A'||_F for the "
              "projector H of the leading n-1 rows A'.\n");
  accuracy_table("Hilbert", hilb);
  accuracy_table("Vandermonde (equispaced points in [0, 1]; m x n, m = 2n is a consistent "
                 "overdetermined fit)", vand);
  timing_table(quick ? 0.002 : 0.05);
  return g_sink == 12345.678 ? 1 : 0;
}
