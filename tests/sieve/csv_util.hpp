// Test helper: reads a timeseries.csv (header row, then numeric rows) into memory.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace pcsim::testing {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  /// Index of the named column (header.size() if absent).
  int col(const std::string& name) const {
    return static_cast<int>(std::find(header.begin(), header.end(), name) - header.begin());
  }
};

inline Csv read_csv(const std::filesystem::path& file) {
  Csv c;
  std::ifstream in(file);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream hs(line);
  while (std::getline(hs, cell, ',')) c.header.push_back(cell);
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> row;
    // An empty field is a value not defined at that instant (pcsim writes no "nan" token).
    while (std::getline(ls, cell, ','))
      row.push_back(cell.empty() ? std::numeric_limits<double>::quiet_NaN() : std::stod(cell));
    if (!line.empty() && line.back() == ',') row.push_back(std::numeric_limits<double>::quiet_NaN());
    c.rows.push_back(row);
  }
  return c;
}

}  // namespace pcsim::testing
