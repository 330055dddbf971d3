// Pseudo-arclength continuation of periodic orbits (see continuation.hpp).
#include "steady/continuation.hpp"
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "common/format.hpp"

namespace pcsim::steady {

namespace {

// A point of the branch in the variables of the arclength: the state at t0 (physical units),
// the holding forces and the parameter; and the branch's unit tangent there.
struct Tangent {
  Eigen::VectorXd y, H;  // dy/ds (physical), dH/ds
  double p = 0.0;        // dp/ds
};

// The arclength norm: |S dy|²/Z² + dp²/P² (the holding forces follow the state: not measured).
struct Norm {
  Eigen::VectorXd scale;  // S
  double Z = 1.0, P = 1.0;
  double dot(const Eigen::VectorXd& dy1, double dp1, const Eigen::VectorXd& dy2, double dp2) const {
    return scale.cwiseProduct(dy1).dot(scale.cwiseProduct(dy2)) / (Z * Z) + dp1 * dp2 / (P * P);
  }
};

// The tangent at a converged point from its linearization (with ∂r/∂p): the null vector of
// [J, r_p], fixed by ⟨τ, τ_prev⟩ = 1 (continuity of the direction), then normalized.
bool tangent_at(const Linearization& L, const Norm& nm, const Tangent& prev, int ns, Tangent& t) {
  const int m = static_cast<int>(L.basis.cols());
  const int N = m + ns;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N + 1, N + 1);
  A.topLeftCorner(N, N) = L.jacobian;
  A.block(0, N, N, 1) = L.dr_dp;
  const Eigen::VectorXd ty = nm.scale.cwiseProduct(prev.y);  // S τ_y
  A.block(N, 0, 1, m) = (L.basis.transpose() * ty).transpose() / (nm.Z * nm.Z);
  A(N, N) = prev.p / (nm.P * nm.P);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(N + 1);
  rhs[N] = 1.0;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  if (!lu.isInvertible()) return false;
  const Eigen::VectorXd v = lu.solve(rhs);
  if (!v.allFinite()) return false;
  t.y = (L.basis * v.head(m)).cwiseQuotient(nm.scale);
  t.H = v.segment(m, ns);
  t.p = v[N];
  const double len = std::sqrt(nm.dot(t.y, t.p, t.y, t.p));
  if (!(len > 0)) return false;
  t.y /= len;
  t.H /= len;
  t.p /= len;
  return true;
}

}  // namespace

Branch continue_branch(const std::function<OrbitProblem(double)>& problem_of,
                       const std::function<ParameterDerivative(double)>& derivative_at,
                       const OrbitPoint& guess, const ContinuationOptions& o) {
  Branch b;
  // One scaling of the state along the whole branch (that of the start): the residual's
  // scale must not change with the parameter, or the corrector's Jacobian misses its change.
  double omega_scale = 0.0;
  try {
    const OrbitProblem p0 = problem_of(o.p_start);
    omega_scale = 6.28318530717958647692 / (p0.periods * p0.period);
  } catch (const std::exception& e) {
    b.message = e.what();
    return b;
  }
  const auto problem_at = [&](double p) {
    OrbitProblem pr = problem_of(p);
    pr.velocity_scale = omega_scale;
    return pr;
  };
  const double range = o.p_stop - o.p_start;
  const double dir = range >= 0 ? 1.0 : -1.0;
  Norm nm;
  nm.P = std::abs(range) > 0 ? std::abs(range) : std::max(1.0, std::abs(o.p_start));
  const double ds_max = 1.0 / std::max(1, o.count - 1);
  const double ds_min = ds_max * o.min_step_fraction;

  // The first orbit, by Newton shooting at p_start.
  OrbitResult r0;
  try {
    r0 = find_orbit(problem_at(o.p_start), guess, o.shooting);
  } catch (const std::exception& e) {
    b.message = e.what();
    return b;
  }
  b.integrations += r0.integrations;
  b.steps += r0.steps;
  if (!r0.converged) {
    b.message = "no orbit at the start " + format_significant(o.p_start, 9) + ": " + r0.message;
    return b;
  }
  const int ns = static_cast<int>(r0.point.H.size());
  double p = o.p_start;
  OrbitPoint x = r0.point;
  Linearization L;
  {
    Shooter sh(problem_at(p), o.shooting);
    const ParameterDerivative d = derivative_at(p);
    L = sh.linearize(x, &d);
    ++b.integrations;
    b.steps += L.steps;
    if (!L.ok) {
      b.message = "the start's linearization: " + L.message;
      return b;
    }
    nm.scale = L.scale;
  }
  // The state's scale in the arclength: three times the largest orbit amplitude met so far, or
  // the state's change over the range at the start's rate if larger (steps then follow the
  // parameter where the response is smooth, and bend with the branch at resonances and folds).
  nm.Z = std::max(3 * L.amplitude, 1e3 * o.shooting.atol);
  Tangent tau;
  {
    Tangent start;
    start.y = Eigen::VectorXd::Zero(x.y.size());
    start.H = Eigen::VectorXd::Zero(ns);
    start.p = dir;
    if (!tangent_at(L, nm, start, ns, tau)) {
      b.message = "the branch's tangent at the start is undefined (a singular point)";
      return b;
    }
    // The state's scale also covers how far the state moves over the whole range at the
    // start's rate (a parameter that moves the orbit as a whole, e.g. a held position, rather
    // than its amplitude).
    if (std::abs(tau.p) > 0) {
      const double rate = nm.scale.cwiseProduct(tau.y).norm() / std::abs(tau.p);  // |S dy/dp|
      if (rate * nm.P > nm.Z) {
        nm.Z = rate * nm.P;
        if (!tangent_at(L, nm, start, ns, tau)) {
          b.message = "the branch's tangent at the start is undefined (a singular point)";
          return b;
        }
      }
    }
  }
  BranchPoint first;
  first.p = p;
  first.x = x;
  first.floquet = r0.floquet;
  first.amplitude = L.amplitude;
  first.iterations = static_cast<int>(r0.history.size());
  first.residual = r0.residual;
  first.tangent_p = tau.p;
  b.points.push_back(first);

  double ds = ds_max;
  while (static_cast<int>(b.points.size()) < o.max_points) {
    // Predictor.
    OrbitPoint xp;
    xp.y = x.y + ds * tau.y;
    xp.H = x.H + ds * tau.H;
    const double pp = p + ds * tau.p;
    bool ok = false;
    int it = 0;
    OrbitPoint xc = xp;
    double pc = pp;
    Linearization Lc;
    std::string why;
    try {
      std::string msg;
      if (!Shooter(problem_at(pc), o.shooting).project(xc, msg)) throw std::runtime_error(msg);
      // Corrector: Newton on [r(x, p) = 0; ⟨τ, X − X_pred⟩ = 0].
      double prev_corr = INFINITY;
      for (it = 1; it <= o.corrector_iterations; ++it) {
        Shooter sh(problem_at(pc), o.shooting);
        const ParameterDerivative d = derivative_at(pc);
        Lc = sh.linearize(xc, &d);
        ++b.integrations;
        b.steps += Lc.steps;
        if (!Lc.ok) throw std::runtime_error(Lc.message);
        const int m = static_cast<int>(Lc.basis.cols());
        const int N = m + ns;
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N + 1, N + 1);
        A.topLeftCorner(N, N) = Lc.jacobian;
        A.block(0, N, N, 1) = Lc.dr_dp;
        const Eigen::VectorXd sty = nm.scale.cwiseProduct(tau.y);
        A.block(N, 0, 1, m) = (Lc.basis.transpose() * sty).transpose() / (nm.Z * nm.Z);
        A(N, N) = tau.p / (nm.P * nm.P);
        Eigen::VectorXd rhs(N + 1);
        rhs.head(N) = -Lc.residual;
        rhs[N] = -nm.dot(tau.y, tau.p, xc.y - xp.y, pc - pp);
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
        const Eigen::VectorXd delta = lu.solve(rhs);
        if (!lu.isInvertible() || !delta.allFinite()) throw std::runtime_error("singular bordered system");
        const double corr = sh.correction_norm(xc, Lc, delta.head(N));
        const double dpc = delta[N];
        OrbitPoint xn;
        if (!sh.advance(xc, Lc, delta.head(N), 1.0, xn, msg)) throw std::runtime_error(msg);
        pc += dpc;
        if (dpc != 0 && !Shooter(problem_at(pc), o.shooting).project(xn, msg)) throw std::runtime_error(msg);
        xc = xn;
        // Converged: the correction is a small fraction of the integration tolerance, or the
        // residual is below the tolerance and the corrections stopped shrinking (what is left
        // is the integration's error amplified by the system's condition).
        const bool small = corr <= o.shooting.newton_tol;
        const bool stalled = Lc.residual_norm <= 1.0 && corr <= 10.0 && corr > 0.5 * prev_corr;
        prev_corr = corr;
        if ((small || stalled) && std::abs(dpc) <= 1e-8 * nm.P) {
          ok = true;
          break;
        }
      }
      if (!ok) why = "the corrector did not converge in " + counted(o.corrector_iterations, "iteration");
    } catch (const std::exception& e) {
      ok = false;
      why = e.what();
    }
    if (!ok) {
      ds *= 0.5;
      if (ds < ds_min) {
        b.message = "the continuation stopped at " + format_significant(p, 9) +
                    ": the step fell below its minimum (" + why + ")";
        return b;
      }
      continue;
    }
    // Accepted: the new tangent (direction continued), stability, folds.
    nm.Z = std::max(nm.Z, 3 * Lc.amplitude);
    Tangent tn;
    if (!tangent_at(Lc, nm, tau, ns, tn)) {
      b.message = "the branch's tangent is undefined at " + format_significant(pc, 9) +
                  " (a branch point?)";
      return b;
    }
    BranchPoint bp;
    bp.p = pc;
    bp.x = xc;
    bp.floquet = Shooter(problem_at(pc), o.shooting).floquet(Lc);
    bp.amplitude = Lc.amplitude;
    bp.iterations = it;
    bp.residual = Lc.residual_norm;
    bp.tangent_p = tn.p;
    if (tn.p * tau.p < 0) {
      bp.fold_before = true;
      // p(s) with p' linear between the points: its extremum.
      const double t0 = tau.p, t1 = tn.p;
      const double sstar = -t0 * ds / (t1 - t0);
      bp.fold_p = p + t0 * sstar / 2;
    }
    // Past the end: the last point exactly at p_stop (Newton at fixed p from the interpolant).
    if ((pc - o.p_stop) * dir >= 0) {
      const double f = (o.p_stop - p) / (pc - p);
      OrbitPoint g;
      g.y = x.y + f * (xc.y - x.y);
      g.H = x.H + f * (xc.H - x.H);
      const OrbitResult re = find_orbit(problem_at(o.p_stop), g, o.shooting);
      b.integrations += re.integrations;
      b.steps += re.steps;
      if (re.converged && !bp.fold_before) {
        bp.p = o.p_stop;
        bp.x = re.point;
        bp.floquet = re.floquet;
        bp.iterations = static_cast<int>(re.history.size());
        bp.residual = re.residual;
      }
      b.points.push_back(bp);
      b.complete = true;
      return b;
    }
    if ((pc - o.p_start) * dir < -0.05 * nm.P) {
      b.points.push_back(bp);
      b.message = "the branch turned back past the start at " + format_significant(pc, 9);
      return b;
    }
    b.points.push_back(bp);
    x = xc;
    p = pc;
    tau = tn;
    if (it <= 3) ds = std::min(ds * 1.5, ds_max);
    else if (it >= 6) ds *= 0.6;
  }
  b.message = "the continuation stopped after " + counted(o.max_points, "point");
  return b;
}

}  // namespace pcsim::steady
