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
