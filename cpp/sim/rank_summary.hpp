// What a run adds to its output where the rank of its active constraints is below their number
// or changes (issue 21, docs/redundant.md): the summary's "rank" object, events.csv rows and the
// report's lines. Runs whose rows keep full rank write exactly what they wrote before.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mech/simulation.hpp"

namespace pcsim::sim {

/// summary.json "rank" (null when the rows have full rank at the start and never lose it):
/// {rows, rank_start, threshold, dependent_start: [names],
///  indeterminate: {from, nullity, rows: [names]} (only when rank_start < rows),
///  changes: [{t, t_from, t_to (null: to the end), rank_before, rank, sigma, dependent: [names]}]}.
nlohmann::json rank_summary(const mech::SimulationResult& r, const std::vector<std::string>& active,
                            double t0);

/// events.csv rows for the rank changes, in events.csv's columns (docs/switching.md): kind
/// rank_lost at t_from and rank_regained at t_to, one row per dependent constraint, mode_before
/// and mode_after the ranks before and after, the other columns empty.
std::vector<std::pair<double, std::string>> rank_event_rows(const nlohmann::json& rank);

/// The report's lines for a run's rank object ("" for null).
std::string rank_report(const nlohmann::json& rank);

}  // namespace pcsim::sim
