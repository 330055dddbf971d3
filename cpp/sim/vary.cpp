// Parsing and checking of --vary specifications; the grid they span.
#include "sim/vary.hpp"

#include <charconv>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <set>
#include <string_view>
#include <system_error>

#include "common/error.hpp"

namespace pcsim::sim {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t pos = s.find(sep, start);
    parts.push_back(s.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return parts;
}

[[noreturn]] void reject(const std::string& spec, const std::string& why) {
  throw InputError("--vary '" + spec + "': " + why);
}

/// A finite number written in full (no trailing text), or reject naming the value.
double parse_value(const std::string& spec, std::string_view text) {
  std::string_view t = trim(text);
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size())
    reject(spec, "value '" + std::string(trim(text)) + "' is not a number");
  if (!std::isfinite(v)) reject(spec, "value '" + std::string(trim(text)) + "' is not finite");
  return v;
}

/// Splits KEY=REST and checks that KEY is a numeric key of the case.
std::pair<std::string, std::string_view> split_key(const std::string& spec,
                                                   const sim::Case& base) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos)
    reject(spec, "expected KEY=START:STOP:COUNT, KEY=v1,v2,... or KEY=LOW:HIGH");
  std::string key(trim(std::string_view(spec).substr(0, eq)));
  if (key.empty()) reject(spec, "the key is empty");
  if (!sim::is_numeric_key(base, key)) {
    if (base.table.at_path(key))
      reject(spec, "key '" + key + "' is not numeric (only numeric case keys can be varied)");
    reject(spec, "unknown key '" + key + "' (use a dotted case key such as parameters.omega)");
  }
  return {key, std::string_view(spec).substr(eq + 1)};
}

/// Applies `text` to a copy of the case so a value the case rejects stops the study now.
void check_value(const std::string& spec, const sim::Case& base, const std::string& key,
                 const std::string& text) {
  sim::Case probe = base;
  try {
    sim::set_value(probe, {key, text});
  } catch (const InputError& e) {
    reject(spec, "value " + text + " is rejected by the case: " + e.what());
  }
}

}  // namespace

double round_decimal(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  double r = v;
  std::from_chars(buf, buf + std::strlen(buf), r);
  return r;
}


void check_distinct_keys(const std::vector<std::string>& keys) {
  std::set<std::string> seen;
  for (const auto& k : keys)
    if (!seen.insert(k).second) throw InputError("--vary: key '" + k + "' is varied twice");
}

Axis parse_vary(const std::string& spec, const sim::Case& base) {
  auto [key, rest] = split_key(spec, base);
  Axis axis{key, {}};
  const auto fields = split(rest, ':');
  if (fields.size() == 3) {  // START:STOP:COUNT
    const double start = parse_value(spec, fields[0]);
    const double stop = parse_value(spec, fields[1]);
    const std::string_view count_text = trim(fields[2]);
    long long count = -1;
    const auto [end, ec] =
        std::from_chars(count_text.data(), count_text.data() + count_text.size(), count);
    if (count_text.empty() || ec != std::errc() || end != count_text.data() + count_text.size())
      reject(spec, "COUNT '" + std::string(count_text) + "' is not a whole number");
    if (count <= 0) reject(spec, "COUNT must be at least 1, got " + std::string(count_text));
    if (stop < start)
      reject(spec, "reversed range: STOP " + format_number(stop) + " < START " +
                       format_number(start) + " (write START:STOP with START <= STOP)");
    if (count == 1 && stop != start) reject(spec, "COUNT 1 needs START == STOP");
    if (static_cast<unsigned long long>(count) > Grid::max_points())
      reject(spec, "COUNT " + std::string(count_text) + " is too large");
    for (long long i = 0; i < count; ++i) {
      // Evenly spaced, ends exactly START and STOP; inner values rounded to 12 significant
      // digits so that 0.1 steps read 0.3, not 0.30000000000000004 (the case gets exactly
      // the value written to the CSV either way).
      const double v = i == count - 1 ? stop
                                      : start + (stop - start) * static_cast<double>(i) /
                                                    static_cast<double>(count - 1);
      axis.texts.push_back(format_number(round_decimal(v)));
    }
  } else if (fields.size() == 1) {  // v1,v2,...
    for (std::string_view item : split(rest, ','))
      axis.texts.push_back(format_number(parse_value(spec, item)));
  } else {
    reject(spec, "expected START:STOP:COUNT or a list v1,v2,...");
  }
  // A value given twice would run the same point twice (and make two rows of one point).
  for (std::size_t i = 0; i < axis.texts.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (std::stod(axis.texts[i]) == std::stod(axis.texts[j]))
        reject(spec, "value " + axis.texts[i] + " appears twice (each design point runs once; "
                     "remove the duplicate)");
  if (sim::is_integer_key(base, key))
    for (const auto& t : axis.texts)
      if (t.find_first_of(".eE") != std::string::npos || t.find("inf") != std::string::npos)
        reject(spec, "key '" + key + "' takes integers, got " + t);
  for (const auto& t : axis.texts) check_value(spec, base, key, t);
  return axis;
}

Bounds parse_bounds(const std::string& spec, const sim::Case& base) {
  auto [key, rest] = split_key(spec, base);
  if (sim::is_integer_key(base, key))
    reject(spec, "key '" + key + "' takes integers, and the optimizer (COBYLA) moves continuous "
                 "design keys; sweep it instead (pcsim sweep --vary " + key + "=...)");
  const auto fields = split(rest, ':');
  if (fields.size() != 2) reject(spec, "expected KEY=LOW:HIGH");
  Bounds b{key, parse_value(spec, fields[0]), parse_value(spec, fields[1])};
  if (b.high < b.low)
    reject(spec, "reversed range: HIGH " + format_number(b.high) + " < LOW " +
                     format_number(b.low));
  if (!(b.low < b.high)) reject(spec, "LOW must be below HIGH");
  check_value(spec, base, key, format_number(b.low));
  check_value(spec, base, key, format_number(b.high));
  return b;
}

Grid::Grid(std::vector<Axis> axes) : axes_(std::move(axes)) {
  size_ = 1;
  for (const auto& a : axes_) {
    if (a.texts.empty()) throw InputError("--vary '" + a.key + "': no values");
    if (size_ > max_points() / a.texts.size())
      throw InputError("the grid has more than " + std::to_string(max_points()) + " points");
    size_ *= a.texts.size();
  }
}

std::vector<std::size_t> Grid::coords(std::size_t i) const {
  std::vector<std::size_t> c(axes_.size());
  for (std::size_t k = axes_.size(); k-- > 0;) {
    c[k] = i % axes_[k].texts.size();
    i /= axes_[k].texts.size();
  }
  return c;
}

std::vector<std::string> Grid::texts(std::size_t i) const {
  const auto c = coords(i);
  std::vector<std::string> t(axes_.size());
  for (std::size_t k = 0; k < axes_.size(); ++k) t[k] = axes_[k].texts[c[k]];
  return t;
}

Grid make_grid(const std::vector<std::string>& specs, const sim::Case& base) {
  std::vector<Axis> axes;
  std::vector<std::string> keys;
  for (const auto& s : specs) {
    axes.push_back(parse_vary(s, base));
    keys.push_back(axes.back().key);
  }
  check_distinct_keys(keys);
  return Grid(std::move(axes));
}

sim::Case Grid::point_case(const sim::Case& base, std::size_t i) const {
  sim::Case c = base;
  const auto t = texts(i);
  for (std::size_t k = 0; k < axes_.size(); ++k) sim::set_value(c, {axes_[k].key, t[k]});
  return c;
}

}  // namespace pcsim::sim
