// Accurate extremes of a smooth scalar signal known through a dense-output evaluator: sampled
// on a grid, then refined by successive parabolic interpolation around the best sample.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace pcsim::sim {

/// The running maximum of a signal (for a minimum, track the negated signal).
struct RunningMax {
  double value = -std::numeric_limits<double>::infinity();
  double time = std::numeric_limits<double>::quiet_NaN();
  void offer(double v, double t) {
    if (v > value) { value = v; time = t; }
  }
};

/// The abscissa of the vertex of the parabola through (x0, f0), (x1, f1), (x2, f2); NaN if the
/// three points are collinear.
inline double parabola_vertex(double x0, double f0, double x1, double f1, double x2, double f2) {
  const double d1 = (x1 - x0) * (f1 - f2), d2 = (x1 - x2) * (f1 - f0);
  const double den = d1 - d2;
  if (den == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return x1 - 0.5 * ((x1 - x0) * d1 - (x1 - x2) * d2) / den;
}

/// The value at the vertex of the parabola through three points (the largest value of a
/// maximum's parabola); -inf if they are collinear or the parabola opens upward.
inline double parabola_peak(double x0, double f0, double x1, double f1, double x2, double f2) {
  const double x = parabola_vertex(x0, f0, x1, f1, x2, f2);
  if (!std::isfinite(x)) return -std::numeric_limits<double>::infinity();
  // Lagrange form at x.
  const double l0 = (x - x1) * (x - x2) / ((x0 - x1) * (x0 - x2));
  const double l1 = (x - x0) * (x - x2) / ((x1 - x0) * (x1 - x2));
  const double l2 = (x - x0) * (x - x1) / ((x2 - x0) * (x2 - x1));
  const double a = f0 / ((x0 - x1) * (x0 - x2)) + f1 / ((x1 - x0) * (x1 - x2)) +
                   f2 / ((x2 - x0) * (x2 - x1));  // leading coefficient
  if (!(a < 0)) return -std::numeric_limits<double>::infinity();
  return l0 * f0 + l1 * f1 + l2 * f2;
}

/// Given samples f(s_0..s_K) on increasing s (K >= 2) of a smooth function available as
/// `eval`, offers the maximum over [s_0, s_K] to `best`, to the accuracy of `eval`: the best
/// sample is bracketed by its neighbours and the vertex of the parabola through the three best
/// points is evaluated, `iterations` times (superlinear for a smooth peak). When the best
/// sample is an end point, the parabola through the three end samples tells whether the peak
/// lies inside the first (last) sub-interval; if it lies beyond, the neighbouring interval
/// contains it and the end sample is this interval's maximum. (A kink, such as |R_s| crossing
/// zero, inside an end sub-interval is not seen by the parabola: it is found only to the
/// sampling's resolution.) With value_rtol > 0 the
/// refinement also stops once the parabola through the bracket predicts no gain above
/// value_rtol |f(m)|: the value, which is what is reported, has converged (a smooth peak's
/// position converges only like the square root of its value).
inline void refine_max(const std::vector<double>& s, const std::vector<double>& f,
                       const std::function<double(double)>& eval, RunningMax& best,
                       int iterations = 4, double value_rtol = 0.0) {
  const int K = static_cast<int>(s.size()) - 1;
  int i = static_cast<int>(std::max_element(f.begin(), f.end()) - f.begin());
  best.offer(f[i], s[i]);
  if (!std::isfinite(f[i])) return;
  double a, fa, m, fm, b, fb;
  if (i == 0 || i == K) {
    const int e = i, n1 = (i == 0) ? 1 : K - 1, n2 = (i == 0) ? 2 : K - 2;
    const double x = parabola_vertex(s[e], f[e], s[n1], f[n1], s[n2], f[n2]);
    const double lo = std::min(s[e], s[n1]), hi = std::max(s[e], s[n1]);
    if (!(x > lo && x < hi)) return;  // the peak is beyond this interval's end
    const double fx = eval(x);
    best.offer(fx, x);
    if (!(fx > f[e])) return;
    a = lo; b = hi; m = x; fm = fx;
    fa = (lo == s[e]) ? f[e] : f[n1];
    fb = (hi == s[e]) ? f[e] : f[n1];
  } else {
    a = s[i - 1]; fa = f[i - 1]; m = s[i]; fm = f[i]; b = s[i + 1]; fb = f[i + 1];
  }
  best.offer(fa, a); best.offer(fb, b); best.offer(fm, m);
  // Now a < m < b with f(m) >= f(a), f(b): a bracketed maximum.
  for (int it = 0; it < iterations; ++it) {
    if (value_rtol > 0 && parabola_peak(a, fa, m, fm, b, fb) - fm <= value_rtol * std::abs(fm)) break;
    double x = parabola_vertex(a, fa, m, fm, b, fb);
    if (std::isnan(x)) break;
    // Keep the trial strictly inside the bracket and away from m.
    const double eps = 1e-3 * (b - a);
    if (!(x > a + eps && x < b - eps) || std::abs(x - m) < 1e-9 * (b - a)) {
      x = (m - a > b - m) ? 0.5 * (a + m) : 0.5 * (m + b);
    }
    const double fx = eval(x);
    best.offer(fx, x);
    if (fx >= fm) {
      if (x < m) { b = m; fb = fm; } else { a = m; fa = fm; }
      m = x; fm = fx;
    } else {
      if (x < m) { a = x; fa = fx; } else { b = x; fb = fx; }
    }
    if (b - a < 1e-12 * std::max(1.0, std::abs(m))) break;
  }
}

/// refine_max, but only when the samples promise a value above best.value: the best sample
/// exceeds it, or the parabola through the best sample and its neighbours (through the three
/// end samples, when the best is an end) peaks above it. A periodic signal's later peaks then
/// cost no evaluations unless they may beat the maximum found so far.
inline void refine_max_if_promising(const std::vector<double>& s, const std::vector<double>& f,
                                    const std::function<double(double)>& eval, RunningMax& best,
                                    int iterations = 4, double value_rtol = 0.0) {
  const int K = static_cast<int>(s.size()) - 1;
  const int i = static_cast<int>(std::max_element(f.begin(), f.end()) - f.begin());
  bool promising = f[i] > best.value || !std::isfinite(f[i]);
  if (!promising) {
    // The parabola's peak estimates the true one with an error of the order of its own rise
    // above the best sample (the samples' spacing to the fourth against to the second power),
    // so a step whose estimate comes within that rise of the best value is refined too.
    const int c = (i == 0) ? 1 : (i == K ? K - 1 : i);
    const double p = parabola_peak(s[c - 1], f[c - 1], s[c], f[c], s[c + 1], f[c + 1]);
    promising = std::isfinite(p) && p + (p - f[i]) > best.value;
  }
  if (promising) refine_max(s, f, eval, best, iterations, value_rtol);
}

}  // namespace pcsim::sim

namespace pcsim::sim {

/// Whether the samples f(s_0..s_K) promise a maximum above best.value (the test of
/// refine_max_if_promising): the best sample exceeds it, or the parabola through the best sample
/// and its neighbours peaks within its own rise of it.
inline bool max_promising(const double* s, const double* f, int K, const RunningMax& best) {
  int i = 0;
  for (int k = 1; k <= K; ++k)
    if (f[k] > f[i]) i = k;
  if (f[i] > best.value || !std::isfinite(f[i])) return true;
  const int c = (i == 0) ? 1 : (i == K ? K - 1 : i);
  const double p = parabola_peak(s[c - 1], f[c - 1], s[c], f[c], s[c + 1], f[c + 1]);
  return std::isfinite(p) && p + (p - f[i]) > best.value;
}

/// The maximum of samples f_0..f_M of a smooth signal on the equispaced grid s_j = s_0 + j d,
/// offered to `best` without evaluating anything: the best sample, then the peak of the quartic
/// through the five samples around it, where that peak lies within a grid interval of the best
/// sample (an interior maximum, found by Newton's method on the quartic's derivative) and rises
/// above the best sample by no more than the samples vary around it (else, at a kink or where
/// the quartic does not fit the signal, the best sample stands). The quartic's error is of the
/// order of d^5 times the signal's fifth derivative: the bounded-cost monitor's refinement.
/// ends_over_two: at an end of the grid the fall is measured over the two samples beside it
/// (accepts a peak anywhere in the end interval; false: the behaviour before issue 23's second
/// part, which the stored summaries of models under 60 coordinates, bricard_a04's, carry).
inline void refine_max_on_grid(const double* s, const double* f, int M, RunningMax& best,
                               bool ends_over_two = false) {
  int i = 0;
  for (int k = 1; k <= M; ++k)
    if (f[k] > f[i]) i = k;
  best.offer(f[i], s[i]);
  if (!std::isfinite(f[i]) || M < 4) return;
  const int j0 = std::min(std::max(i - 2, 0), M - 4);
  // p(u) = f_j0 + u D1 + u(u-1)/2 D2 + u(u-1)(u-2)/6 D3 + u(u-1)(u-2)(u-3)/24 D4 (forward
  // differences), x = s_j0 + u d.
  const double* g = f + j0;
  for (int k = 0; k < 5; ++k)
    if (!std::isfinite(g[k])) return;
  const double D1 = g[1] - g[0], D2 = g[2] - 2 * g[1] + g[0], D3 = g[3] - 3 * g[2] + 3 * g[1] - g[0],
               D4 = g[4] - 4 * g[3] + 6 * g[2] - 4 * g[1] + g[0];
  // Monomial coefficients of p(u) = c0 + c1 u + c2 u^2 + c3 u^3 + c4 u^4.
  const double c1 = D1 - D2 / 2 + D3 / 3 - D4 / 4, c2 = D2 / 2 - D3 / 2 + 11 * D4 / 24,
               c3 = D3 / 6 - D4 / 4, c4 = D4 / 24;
  // A smooth signal on a fine grid has differences falling by the grid's ratio to the signal's
  // scale with each order; a kink (|R_s| through zero) or noise does not: the best sample stands.
  if (!(std::abs(D3) + std::abs(D4) <= 0.5 * std::abs(D2))) return;
  auto p = [&](double u) { return g[0] + u * (c1 + u * (c2 + u * (c3 + u * c4))); };
  const double ui = i - j0;
  const double lo = std::max(ui - 1, 0.0), hi = std::min(ui + 1, 4.0);
  double u = ui;
  // Start from the parabola through the best sample and its neighbours (inside the grid).
  const int c = (i == 0) ? 1 : (i == M ? M - 1 : i);
  const double vtx = parabola_vertex(c - 1, f[c - 1], c, f[c], c + 1, f[c + 1]);
  if (std::isfinite(vtx)) u = std::min(std::max(vtx - j0, lo), hi);
  for (int it = 0; it < 8; ++it) {
    const double d1 = c1 + u * (2 * c2 + u * (3 * c3 + u * 4 * c4));
    const double d2 = 2 * c2 + u * (6 * c3 + u * 12 * c4);
    if (!(d2 < 0)) return;  // not a maximum of the quartic
    const double step = d1 / d2;
    u -= step;
    if (!(u > lo && u < hi)) return;  // the quartic's peak is beyond the bracket
    if (std::abs(step) < 1e-12) break;
  }
  const double value = p(u);
  // How far the samples fall around the best: over its two neighbours; at an end of the grid
  // (ends_over_two) over the two samples beside it: a peak inside the end interval, at u from
  // the end, rises a u² above the end sample while the next one falls only a (1 - 2u) below it,
  // so from u ~ 0.41 the one-neighbour test rejects it (and the end sample stands, short of the
  // peak by up to a quarter of the curvature term).
  const int e = ends_over_two ? 2 : 1;
  const double left = i > 0 ? f[i - 1] : f[i + e], right = i < M ? f[i + 1] : f[i - e];
  const double spread = f[i] - std::min(left, right);
  if (value >= f[i] && value - f[i] <= spread) best.offer(value, s[j0] + u * (s[1] - s[0]));
}

}  // namespace pcsim::sim
