// The sweep table: which summary.json fields become sweep.csv columns, how a summary is
// flattened into them, and CSV lines written and read back (RFC 4180 quoting).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/case.hpp"
#include "sim/result.hpp"

namespace pcsim::study {

/// The summary columns of sweep.csv for a case, in order. The model's client chooses them (the
/// sieve: amplitude.*, theta_mean, theta_max_abs*, R_u_*, fstar_max, verdicts,
/// first_violation.*, constraint_residual_max, q_end.*, stats.*, then the design margins
/// contact_margin and rolling_margin); any other model has every window extreme
/// (extremes.<column>.min/max/amplitude), q_end.*, qd_end.*, constraint_residual_max and stats.*.
/// Then window_clipped. stats.wall_seconds is left out on purpose: it differs from run to run,
/// and a sweep's table must be identical whatever the number of jobs or ranks.
std::vector<std::string> summary_columns(const sim::Case& c);

/// The last two columns of every row.
inline constexpr const char* kStatusColumn = "status";  ///< "ok" or "error"
inline constexpr const char* kErrorColumn = "error";    ///< the reason of a failed point

/// The values of `columns` for one run of case c, as CSV text: numbers as shortest round-trip
/// decimals, booleans as true/false, null or missing as an empty field. A column is the dotted
/// path of a value in the run's summary.json (sweep.csv's contract: "extremes.x.max",
/// "stats.steps", "q_end.s"), or one of the client's derived columns (e.g. the sieve's margins).
std::vector<std::string> flatten_summary(const sim::RunResult& result, const sim::Case& c,
                                         const std::vector<std::string>& columns);

/// The numeric columns of a flattened summary by name (booleans as 1/0; empty fields left out).
std::map<std::string, double> numeric_fields(const std::vector<std::string>& columns,
                                             const std::vector<std::string>& fields);

/// One CSV line (no newline): fields joined by commas; a field holding a comma, quote or
/// line break is quoted, with quotes doubled; line breaks in fields become spaces.
std::string csv_line(const std::vector<std::string>& fields);

/// Splits one CSV line (without its newline) into fields; nullopt if the quoting is broken.
std::optional<std::vector<std::string>> parse_csv_line(std::string_view line);

/// A whole CSV file: header and rows. Lines that do not parse or have the wrong number of
/// fields are dropped.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// Index of a column by name, or nullopt.
  std::optional<std::size_t> column(std::string_view name) const;
};

/// Reads a CSV file; nullopt if it cannot be read or has no header line.
std::optional<CsvTable> read_csv(const std::filesystem::path& file);

}  // namespace pcsim::study
