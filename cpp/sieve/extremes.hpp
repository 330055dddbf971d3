// Accurate extremes of a smooth scalar signal known through a dense-output evaluator: sampled
// on a grid, then refined by successive parabolic interpolation around the best sample.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace pcsim::sieve {

/// The running maximum of a signal (for a minimum, track the negated signal).
struct RunningMax {
  double value = -std::numeric_limits<double>::infinity();
  double time = std::numeric_limits<double>::quiet_NaN();
  void offer(double v, double t) {
    if (v > value) { value = v; time = t; }
  }
};

/// Given samples f(s_0..s_K) on increasing s (K >= 2) of a smooth function available as
/// `eval`, returns the maximum over [s_0, s_K] to the accuracy of `eval`: the best sample is
/// bracketed by its neighbours and the vertex of the parabola through the three best points
/// is evaluated, `iterations` times (each halves the bracket at least, and converges
/// superlinearly for a smooth peak). Endpoint maxima return the endpoint sample (the
/// neighbouring interval sees the peak if it lies beyond).
inline void refine_max(const std::vector<double>& s, const std::vector<double>& f,
                       const std::function<double(double)>& eval, RunningMax& best,
                       int iterations = 4) {
  const int K = static_cast<int>(s.size()) - 1;
  int i = static_cast<int>(std::max_element(f.begin(), f.end()) - f.begin());
  if (!std::isfinite(f[i])) { best.offer(f[i], s[i]); return; }
  double a, fa, m = s[i], fm = f[i], b, fb;
  if (i == 0) {
    // Maximum at the left end: refine inside [s0, s1] only if the slope turns there.
    a = s[0]; fa = f[0]; m = 0.5 * (s[0] + s[1]); fm = eval(m); b = s[1]; fb = f[1];
    if (fm <= fa) { best.offer(fa, a); return; }
  } else if (i == K) {
    a = s[K - 1]; fa = f[K - 1]; b = s[K]; fb = f[K]; m = 0.5 * (a + b); fm = eval(m);
    if (fm <= fb) { best.offer(fb, b); return; }
  } else {
    a = s[i - 1]; fa = f[i - 1]; b = s[i + 1]; fb = f[i + 1];
  }
  best.offer(fa, a); best.offer(fb, b); best.offer(fm, m);
  // Now a < m < b with f(m) >= f(a), f(b): a bracketed maximum.
  for (int it = 0; it < iterations; ++it) {
    const double d1 = (m - a) * (fm - fb), d2 = (m - b) * (fm - fa);
    const double den = d1 - d2;
    double x;
    if (den == 0.0) break;
    x = m - 0.5 * ((m - a) * d1 - (m - b) * d2) / den;
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

}  // namespace pcsim::sieve
