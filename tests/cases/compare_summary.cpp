// Compares a run's summary.json with a stored reference (the case harness, tests/cases):
// every physical quantity to kDigits significant digits, booleans, strings and nulls exactly.
// Solver statistics and wall time are not compared (they belong to the integrator, not to the
// result).
//
// Why 5 digits: the cases run with rtol = 1e-6; their summaries move by < 1e-5 relative when
// the tolerance is tightened to 1e-11 (test_sieve_run proves < 1e-4; measured ~1e-7) and the
// extremes are refined on the dense output; runs with the other kernel or the DAE form agree
// with the stored references to these 5 digits too (checked when the references were made).
// That leaves room for compiler and Release/Debug rounding, while any real change of the
// model or of the summary logic moves them.
//
// With --exact every number must be equal to the last bit (for the erratum-7 check that the
// printed rolling sign reproduces the references computed before the erratum exactly).
//
// Usage: case_compare_summary [--exact] ACTUAL.json REFERENCE.json  (exit 0: agree, 1: differ)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

constexpr double kDigits = 5;

// Absolute floors: below them a difference is integration noise, not a result. q_end's x, y
// and theta are snapshots of oscillations of amplitude ~2e-5 (m, rad) that pass near zero: an
// integration with rtol 1e-6 places them to ~1e-10 absolute, so they are compared to 1e-9
// (floor 1e-4 times 10^-5). Angles that are zero in the ideal model (theta with lock_theta:
// rounding leaves ~1e-17 rad, and the DAE form ~4e-17) are compared to 1e-14 rad (floor 1e-9),
// far below the ~1e-5 rad the free desk moves; everything else has a negligible floor.
double floor_for(const std::string& path) {
  // End velocities that vanish in exact arithmetic (a constrained coordinate's) are rounding
  // noise of order 1e-15: compared to an absolute 1e-12 (floor 1e-7 times 10^-5). (Window
  // extremes are compared relative to their column's range instead: column_scale.)
  if (path.rfind("/qd_end/", 0) == 0) return 1e-7;
  if (path == "/q_end/x" || path == "/q_end/y" || path == "/q_end/theta") return 1e-4;
  if (path == "/theta_mean") return 1e-8;
  // The normal force and the margins built from it are known to 5 digits of the roller's weight
  // (R_u ~ 5 N, margins ~ 1), not of their own value: in a hopping run R_u_min is the force at
  // lift-off, zero up to rounding (~1e-10 N), whose digits change with the order of operations.
  if (path == "/R_u_min" || path == "/R_u_max") return 1.0;
  if (path == "/R_u_min_over_weight" || path.rfind("/margins/", 0) == 0) return 1.0;
  // A penetration of a contact is compared to 1e-14 m: rounding-level depths (~1e-15 m) are
  // noise, anything a body really sinks in is not.
  if (path.size() >= 16 && path.compare(path.size() - 16, 16, "/penetration_max") == 0) return 1e-9;
  if (path.find("theta") != std::string::npos) return 1e-9;
  return 1e-12;
}

int failures = 0;
bool exact = false;

// The window extremes of a column (extremes.<col>.min/max/amplitude) are compared to 5 digits of
// the column's range max(|min|, |max|), not of each value: the minimum of |R_s|/R_u (a kink at
// zero) or of a velocity that vanishes in exact arithmetic is known to that scale only.
double column_scale = 0.0;

void compare(const nlohmann::json& a, const nlohmann::json& r, const std::string& path) {
  if (path.rfind("/extremes/", 0) == 0 && std::count(path.begin(), path.end(), '/') == 2 &&
      r.is_object()) {
    column_scale = 0.0;
    for (const char* k : {"min", "max"})
      if (r.contains(k) && r[k].is_number())
        column_scale = std::max(column_scale, std::abs(r[k].get<double>()));
    // A column that is zero up to rounding (|values| < 1e-12) is compared to 1e-12 absolute.
    column_scale = std::max(column_scale, 1e-7);
  }
  if (path == "/assumptions/note") return;  // prose about the assumptions, not a result
  if (path == "/stats" || path == "/constraint_residual_max") {
    // Residuals depend on the projection's rounding: only check the order of magnitude.
    if (path == "/constraint_residual_max" && a.is_number() && r.is_number() &&
        a.get<double>() > std::max(100 * r.get<double>(), 1e-9)) {
      std::printf("%s: residual %.3g, reference %.3g\n", path.c_str(), a.get<double>(),
                  r.get<double>());
      ++failures;
    }
    return;
  }
  if (r.is_object()) {
    // The time of the deepest penetration is only a result when the penetration is one: at
    // rounding depth (< 1e-9 m in the reference) any instant of contact is as deep.
    const bool noise_penetration = r.contains("penetration_max") && r["penetration_max"].is_number() &&
                                   std::abs(r["penetration_max"].get<double>()) < 1e-9;
    for (auto it = r.begin(); it != r.end(); ++it) {
      if (noise_penetration && it.key() == "penetration_time" && !exact) continue;
      if (!a.contains(it.key())) {
        std::printf("%s/%s: missing\n", path.c_str(), it.key().c_str());
        ++failures;
        continue;
      }
      compare(a[it.key()], it.value(), path + "/" + it.key());
    }
    return;
  }
  if (r.is_array()) {
    if (!a.is_array() || a.size() != r.size()) {
      std::printf("%s: array size differs\n", path.c_str());
      ++failures;
      return;
    }
    for (std::size_t i = 0; i < r.size(); ++i)
      compare(a[i], r[i], path + "/" + std::to_string(i));
    return;
  }
  if (r.is_number() && a.is_number()) {
    const double x = a.get<double>(), y = r.get<double>();
    const double floor =
        path.rfind("/extremes/", 0) == 0 ? column_scale : floor_for(path);
    const double tol = exact ? 0.0 : std::pow(10.0, -kDigits) * std::max(std::abs(y), floor);
    if (!(std::abs(x - y) <= tol)) {
      std::printf("%s: %.12g, reference %.12g (tolerance %.3g)\n", path.c_str(), x, y, tol);
      ++failures;
    }
    return;
  }
  if (a != r) {
    std::printf("%s: %s, reference %s\n", path.c_str(), a.dump().c_str(), r.dump().c_str());
    ++failures;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "--exact") {
    exact = true;
    ++argv;
    --argc;
  }
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s [--exact] ACTUAL.json REFERENCE.json\n", argv[0]);
    return 2;
  }
  nlohmann::json a, r;
  try {
    std::ifstream fa(argv[1]), fr(argv[2]);
    a = nlohmann::json::parse(fa);
    r = nlohmann::json::parse(fr);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cannot read the summaries: %s\n", e.what());
    return 2;
  }
  compare(a, r, "");
  if (failures && exact) std::printf("%d difference(s)\n", failures);
  if (failures && !exact)
    std::printf("%d difference(s) beyond %g significant digits\n", failures, kDigits);
  return failures ? 1 : 0;
}
