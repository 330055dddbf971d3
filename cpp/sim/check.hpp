// What the engine finds about a case at its initial state, without running it (issue 21,
// `pcsim check`): coordinates and active constraints, whether M is positive definite, the rank
// of the constraint Jacobian g, the degrees of freedom against the Grübler-style count n − m,
// the redundant rows by name, the smallest singular value of g (rows scaled to unit length),
// the initial residuals and the consistent-initial-value correction; and whether the case can
// run. A typed result (CheckReport); the CLI prints format_check of it, Python binds it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/case.hpp"

namespace pcsim::sim {

/// The check of a case at its initial state. The constraint fields are set only when they were
/// computed: rank .. velocity_residual when there are active constraints and the check of the
/// model found no issue; the corrections only when the case can run.
struct CheckReport {
  std::string case_name;                 ///< the case's name
  std::string model;                     ///< the model's name
  std::vector<std::string> coordinates;  ///< the generalized coordinates q (n of them)
  std::vector<std::string> active;       ///< the active constraints (m of them)
  bool mass_positive_definite = false;   ///< M at the initial state: smallest eigenvalue > 1e-13 largest
  double mass_eigenvalue_min = 0.0, mass_eigenvalue_max = 0.0;  ///< M's eigenvalue range
  std::optional<int> rank;               ///< rank of the active rows at the initial state
  std::optional<int> dof;                ///< n − rank (n when m = 0)
  int gruebler = 0;                      ///< the Grübler-style count n − m
  std::vector<std::string> redundant;    ///< the rows that depend on earlier ones, by name
  std::optional<int> null_space_dimension;         ///< m − rank
  std::optional<double> smallest_singular_value;   ///< of g, rows scaled to unit length
  std::optional<double> position_residual, velocity_residual;  ///< initial |Φ|, |g q̇ + g0|
  std::optional<double> correction_pos, correction_vel;        ///< |Δq|₂, |Δq̇|₂ of the correction
  std::string note;                      ///< the check's remark on accepted dependent rows, or ""
  bool can_run = false;
  std::string reason;                    ///< why it cannot run ("" when it can)
};

/// Checks the case at its initial state (t = 0, q0, qd0, the active constraints, the kernel).
/// A case that cannot run is a report with can_run = false and the reason, not an exception;
/// errors of the model itself (e.g. instantiation) propagate as they do for a run.
CheckReport check_case(const Case& c);

/// The text `pcsim check` prints (its standard output), one line per finding.
std::string format_check(const CheckReport& r);

/// The message `pcsim check` exits 2 with when the case cannot run: "case 'NAME' cannot run:
/// REASON" ("" when it can run).
std::string check_refusal(const CheckReport& r);

/// The report as JSON: every field by its name, null where it was not computed.
nlohmann::json to_json(const CheckReport& r);

}  // namespace pcsim::sim
