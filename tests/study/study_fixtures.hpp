// Test fixtures of the study tests: a deterministic fake runner (so the sweep machinery is
// tested without the integrator), a minimal case file, a scratch directory, file helpers.
#pragma once

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "../support/build_tree.hpp"
#include "common/error.hpp"
#include "sieve/source.hpp"
#include "sim/case.hpp"
#include "sim/result.hpp"

namespace study_test {

/// A fresh empty directory under the build tree, removed first if it exists.
inline std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path d = pcsim_test::binary_dir() / "test-scratch" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// The sieve case with every documented default, and a short run (solver.t_end = t_end).
inline const bool kSieveRegistered = (pcsim::sieve::register_sieve(), true);

/// The case file lives beside `dir` (in `<dir>.case/`), not in it: tests use `dir` as a sweep's
/// output directory, which pcsim refuses when it holds a file pcsim did not write.
inline pcsim::sim::Case minimal_case(const std::filesystem::path& dir, double t_end = 0.2) {
  const auto case_dir = dir.parent_path() / (dir.filename().string() + ".case");
  std::filesystem::create_directories(case_dir);
  const auto file = case_dir / "mini.toml";
  std::ofstream(file) << "model = \"sieve\"\n";
  return pcsim::sim::load_case(file, {{"solver.t_end", std::to_string(t_end)}});
}

inline double num(const pcsim::sim::Case& c, const char* key) {
  return c.table.at_path(key).value<double>().value();
}

/// A deterministic stand-in for sieve::run_case: a smooth function of omega, e and s0 in the
/// summary's shape; throws NumericalError for omega > 1000 (a "failed point"); sleeps a
/// value-dependent 0-3 ms so that threads finish out of grid order. Counts its calls.
struct FakeRunner {
  std::shared_ptr<std::atomic<int>> calls = std::make_shared<std::atomic<int>>(0);
  pcsim::sim::RunResult operator()(const pcsim::sim::Case& c) const {
    ++*calls;
    const double w = num(c, "parameters.omega"), e = num(c, "parameters.e");
    const double s0 = num(c, "initial.s0");
    const bool locked = c.table.at_path("constraints.lock_theta").value_or(false);
    std::this_thread::sleep_for(std::chrono::microseconds(
        static_cast<int>(std::fmod(std::abs(w * 7.0 + s0 * 1000.0), 3.0) * 1000)));
    if (w > 1000) throw pcsim::NumericalError("step size too small at t = 0.01, \"fake\"", 0.01);
    const double a = e * w * w / 400.0;
    pcsim::sim::RunResult r;
    nlohmann::json& j = r.additions;  // the sieve's keys
    j["amplitude"] = {{"x", a * 1e-3}, {"y", a * 2e-3}, {"theta", locked ? 0.0 : 1e-4 * s0}};
    j["theta_mean"] = locked ? 0.0 : 1e-6 * s0;
    j["R_u_min_over_weight"] = 1.0 - a / 9.81 * (1.0 + (locked ? 0.5 : 1.0) * s0 * s0);
    j["R_u_min"] = j["R_u_min_over_weight"].get<double>() * 0.5 * 9.81;
    j["R_u_max"] = 2.0 * 0.5 * 9.81;
    j["fstar_max"] = 0.1 + 0.01 * s0 + (locked ? 0.0 : 0.02);
    j["contact_kept"] = j["R_u_min"].get<double>() > 0;
    j["rolling_kept"] = true;
    j["first_violation"] = {{"contact", nullptr}, {"rolling", nullptr}};
    r.constraint_residual_max = 1e-12;
    r.q_end = {{"x", 0.0}, {"y", 0.0}, {"theta", 0.0}, {"s", s0}, {"u", 0.15}, {"phi", 0.0}};
    r.window_clipped = false;
    r.stats = {100 + static_cast<long>(w), 90, 10, 400, 5, 20, 1e-3 * static_cast<double>(*calls)};
    return r;
  }
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace study_test
