// `pcsim response` for a case: the steady state traced along one numeric case key (a model
// parameter, or a held value) by pseudo-arclength continuation over a range, or solved
// independently (in parallel) at listed values; each orbit's one-period summary run in
// parallel; response.csv and response.json with stability, folds and resonances.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/case.hpp"
#include "steady/continuation.hpp"
#include "steady/steady_case.hpp"

namespace pcsim::steady {

struct ResponseOptions {
  /// KEY=START:STOP:COUNT (continuation; the largest step is (STOP − START)/(COUNT − 1)) or
  /// KEY=v1,v2,... (independent Newton solves, in parallel).
  std::string vary;
  int periods = 1;
  OdeMethod method = OdeMethod::automatic;
  unsigned jobs = 0;  ///< threads for the independent work; 0: all cores
  std::optional<std::filesystem::path> out_dir;
  bool summaries = true;  ///< run each orbit's one-period summary (amplitudes, client keys)
};

struct ResponsePoint {
  double p = 0.0;
  bool ok = false;
  std::string error;
  OrbitPoint x;
  Floquet floquet;
  int iterations = 0;
  double residual = 0.0;
  bool fold_before = false;
  double fold_p = 0.0;
  std::optional<sim::RunResult> summary;  ///< the one-period summary (none without summaries)
};

struct ResponseResult {
  std::string key;
  bool continuation = false;
  bool complete = true;      ///< the continuation reached STOP
  std::string message;       ///< why it stopped early
  std::vector<ResponsePoint> points;
  std::vector<std::string> columns;              ///< response.csv header
  std::vector<std::vector<std::string>> rows;    ///< response.csv rows
  nlohmann::json meta;                           ///< response.json
};

/// Runs `pcsim response`. Throws pcsim::InputError for a bad --vary or a case pcsim steady
/// cannot take, pcsim::NumericalError when not a single orbit is found. Writes response.csv
/// and response.json into options.out_dir (as a whole) when given.
ResponseResult response_case(const sim::Case& c, const ResponseOptions& options);

/// The case with one numeric key set to a value (no re-validation: the value was checked by
/// the --vary parser).
sim::Case case_at(const sim::Case& c, const std::string& key, double value);

}  // namespace pcsim::steady
