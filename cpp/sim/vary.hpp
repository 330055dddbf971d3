// The design space of a study: `--vary` specifications parsed and checked against a case, and
// the full grid they span (first axis slowest, like nested loops in the order given).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "common/format.hpp"
#include "sim/case.hpp"

namespace pcsim::sim {

/// One varied case key and the values it takes, as the exact text given to sim::set_value
/// and written to sweep.csv (shortest round-trip decimal for numbers, so the CSV value parses
/// back to the same double).
struct Axis {
  std::string key;
  std::vector<std::string> texts;
};

/// Bounds of one continuous design variable (optimize: `--vary KEY=LOW:HIGH`).
struct Bounds {
  std::string key;
  double low = 0.0;
  double high = 0.0;
};

/// Parses `KEY=START:STOP:COUNT` (COUNT values, evenly spaced, both ends included) or
/// `KEY=v1,v2,...` and checks it against `base` before anything runs. Throws pcsim::InputError
/// naming the specification for: no '=', an unknown key, a key that is not numeric, a
/// non-numeric or non-finite value, a zero or non-integer COUNT, a reversed range
/// (STOP < START), COUNT 1 with START != STOP, and any value the case rejects (set_value's
/// validation, e.g. a negative mass).
Axis parse_vary(const std::string& spec, const sim::Case& base);

/// Parses `KEY=LOW:HIGH` (LOW < HIGH) with the same key and value checks as parse_vary; both
/// bounds must be accepted by the case.
Bounds parse_bounds(const std::string& spec, const sim::Case& base);

/// Throws pcsim::InputError if a key is varied twice.
void check_distinct_keys(const std::vector<std::string>& keys);


/// v rounded to 12 significant decimal digits (grid values that read as the decimals a user
/// typed: -0.4 + 0.1 gives -0.3, not -0.30000000000000004).
double round_decimal(double v);

/// The full grid spanned by the axes. Point i has coordinates coords(i); the last axis varies
/// fastest.
class Grid {
 public:
  Grid() = default;
  /// Throws pcsim::InputError if the grid has more than max_points() points.
  explicit Grid(std::vector<Axis> axes);
  const std::vector<Axis>& axes() const { return axes_; }
  std::size_t size() const { return size_; }
  /// Index of each axis's value at grid point i (i < size()).
  std::vector<std::size_t> coords(std::size_t i) const;
  /// The value texts of grid point i, one per axis.
  std::vector<std::string> texts(std::size_t i) const;
  /// base with every axis key set to its value at grid point i (sim::set_value; it may throw
  /// pcsim::InputError if a combination is invalid).
  sim::Case point_case(const sim::Case& base, std::size_t i) const;
  static constexpr std::size_t max_points() { return 10'000'000; }

 private:
  std::vector<Axis> axes_;
  std::size_t size_ = 1;
};

/// Every `--vary` specification parsed (parse_vary), keys checked distinct, and the grid they
/// span; throws pcsim::InputError before anything runs.
Grid make_grid(const std::vector<std::string>& specs, const sim::Case& base);

}  // namespace pcsim::sim
