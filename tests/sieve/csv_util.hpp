// Test helper: reads a timeseries.csv (header row, then numeric rows) into memory.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
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
    while (std::getline(ls, cell, ',')) row.push_back(std::stod(cell));
    c.rows.push_back(row);
  }
  return c;
}

}  // namespace pcsim::testing
