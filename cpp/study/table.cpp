// Flattening summaries into sweep.csv columns; CSV lines written and read back.
#include "study/table.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/format.hpp"
#include "sim/client.hpp"
#include "sim/run.hpp"
#include "sim/vary.hpp"

namespace pcsim::study {

namespace {

std::string scalar_text(const nlohmann::json& v) {
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer()) return std::to_string(v.get<long long>());
  if (v.is_number()) return csv_number(v.get<double>());  // inf, nan: an empty field
  if (v.is_string()) return v.get<std::string>();
  return "";  // null, or a structure where a scalar was expected
}

}  // namespace

std::vector<std::string> summary_columns(const sim::Case& c) {
  std::vector<std::string> cols;
  if (c.client) cols = c.client->sweep_columns();
  if (cols.empty()) {
    const auto ts = sim::timeseries_columns(c);
    const std::size_t modes = sim::switched_contacts(c).size();
    for (std::size_t i = 1; i + 2 + modes < ts.size(); ++i)
      for (const char* part : {"min", "max", "amplitude"})
        cols.push_back("extremes." + ts[i] + "." + part);
    for (const auto& q : c.model->coordinates()) cols.push_back("q_end." + q);
    for (const auto& q : c.model->coordinates()) cols.push_back("qd_end." + q + "_d");
    cols.push_back("constraint_residual_max");
    for (const char* st : {"steps", "accepted", "rejected", "f_evals", "jacobians", "lu_decompositions"})
      cols.push_back(std::string("stats.") + st);
  }
  // Switching (issue 12): per switched contact, what it did over the summary window.
  for (const auto& u : sim::switched_contacts(c))
    for (const char* k : {"contact_fraction", "lift_offs", "impacts", "max_flight_height",
                          "max_impact_velocity", "slip_distance", "energy_impacts", "energy_friction"})
      cols.push_back("switching.contacts." + u + ".window." + k);
  cols.push_back("window_clipped");
  return cols;
}

std::vector<std::string> flatten_summary(const sim::RunResult& result, const sim::Case& c,
                                         const std::vector<std::string>& columns) {
  const std::map<std::string, double> derived =
      c.client ? c.client->derived_columns(result, c) : std::map<std::string, double>{};
  std::vector<std::string> fields;
  fields.reserve(columns.size());
  for (const auto& col : columns) {
    if (auto d = derived.find(col); d != derived.end()) {
      fields.push_back(csv_number(d->second));
      continue;
    }
    fields.push_back(scalar_text(result.value(col)));
  }
  return fields;
}

std::map<std::string, double> numeric_fields(const std::vector<std::string>& columns,
                                             const std::vector<std::string>& fields) {
  std::map<std::string, double> out;
  for (std::size_t i = 0; i < columns.size() && i < fields.size(); ++i) {
    const std::string& f = fields[i];
    if (f == "true") {
      out[columns[i]] = 1.0;
    } else if (f == "false") {
      out[columns[i]] = 0.0;
    } else if (!f.empty()) {
      double v = 0.0;
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (ec == std::errc() && end == f.data() + f.size()) out[columns[i]] = v;
    }
  }
  return out;
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    std::string f = fields[i];
    for (auto& ch : f)
      if (ch == '\n' || ch == '\r') ch = ' ';
    if (f.find_first_of(",\"") == std::string::npos) {
      line += f;
    } else {
      line += '"';
      for (char ch : f) {
        if (ch == '"') line += '"';
        line += ch;
      }
      line += '"';
    }
  }
  return line;
}

std::optional<std::vector<std::string>> parse_csv_line(std::string_view line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  bool was_quoted = false;  // the current field was a quoted one that has closed
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"') {
        if (i + 1 < line.size() && line[i + 1] == '"') {
          fields.back() += '"';
          ++i;
        } else {
          quoted = false;
          was_quoted = true;
        }
      } else {
        fields.back() += ch;
      }
    } else if (ch == ',') {
      fields.emplace_back();
      was_quoted = false;
    } else if (ch == '"' && fields.back().empty() && !was_quoted) {
      quoted = true;
    } else if (was_quoted || ch == '"' || ch == '\r' || ch == '\n') {
      return std::nullopt;  // text after a closing quote, or a stray quote
    } else {
      fields.back() += ch;
    }
  }
  if (quoted) return std::nullopt;
  return fields;
}

std::optional<std::size_t> CsvTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  return std::nullopt;
}

std::optional<CsvTable> read_csv(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::string line;
  if (!std::getline(in, line)) return std::nullopt;
  auto header = parse_csv_line(line);
  if (!header) return std::nullopt;
  CsvTable t{*header, {}};
  while (std::getline(in, line)) {
    auto row = parse_csv_line(line);
    if (row && row->size() == t.header.size()) t.rows.push_back(std::move(*row));
  }
  return t;
}

}  // namespace pcsim::study
