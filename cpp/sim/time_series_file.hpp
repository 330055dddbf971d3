// A run directory's time series read back, for pcsim plot and pcsim animate: timeseries.csv, or
// timeseries.npy as output.format = "npy" writes it (RowWriter::Npy), each checked whole and read
// into the same rows.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pcsim::sim {

/// The rows of a time series as the run handed them to its writer: per row one value per column;
/// a value the run did not define (an empty CSV field, a NaN of the .npy) is NaN; the last
/// `label_columns` columns (mode_<contact> of a switching run) hold the index of their text in
/// `labels`.
struct TimeSeries {
  std::filesystem::path file;
  std::vector<std::string> header;
  int label_columns = 0;
  std::vector<std::string> labels;
  std::vector<double> values;  ///< row after row, header.size() values each

  std::size_t rows() const { return header.empty() ? 0 : values.size() / header.size(); }
  double at(std::size_t row, std::size_t column) const { return values[row * header.size() + column]; }
  const std::string& label(std::size_t row, std::size_t column) const {
    return labels[static_cast<std::size_t>(at(row, column))];
  }
};

/// The file of dir's time series: dir/timeseries.csv, or else dir/timeseries.npy when it exists;
/// the path of the CSV when neither does.
std::filesystem::path time_series_file(const std::filesystem::path& dir);

/// The fields of a line of a CSV file pcsim writes (its fields hold no commas: no quoting).
std::vector<std::string> split_csv_fields(const std::string& line);

/// The whole contents of `file`, a regular file of at most `max_bytes` (`what` names it in the
/// message). InputError naming the file otherwise.
std::string read_run_file(const std::filesystem::path& file, std::uint64_t max_bytes, const std::string& what);

/// Reads the time series `file` (timeseries.csv or timeseries.npy, told by its extension) of at
/// most `max_bytes`. Throws InputError naming the file and what was expected (exit 2) when it is
/// not a regular file or larger, or is not a time series as pcsim writes it: the first column
/// not 't', a row of the CSV with another number of fields, a field that is not a number, the
/// mode_ labels not the last columns; no rows or a cut-off last row (`half_written` is added,
/// saying what to do); a .npy that is not read_npy's.
TimeSeries read_time_series(const std::filesystem::path& file, std::uint64_t max_bytes,
                            const std::string& half_written);

/// The layout of a timeseries.npy, from its header.
struct NpyLayout {
  std::vector<std::string> names;  ///< the fields (the CSV's columns)
  std::vector<int> widths;         ///< per field: 0 for '<f8', n for a label '|Sn'
  std::uint64_t rows = 0;          ///< the shape (rows,)
  std::uint64_t data_offset = 0;   ///< the bytes before the first record
  std::uint64_t record_bytes = 0;
};

/// Checks the bytes of a whole .npy file against what RowWriter::Npy writes and returns its
/// layout: the magic string and version 1.0 or 2.0, a header that lies within the file and ends
/// in '\n', a dictionary of exactly 'descr', 'fortran_order' and 'shape'; descr a list of named
/// fields, identifiers, each little-endian float64 '<f8' or, after all of those, a byte string
/// '|Sn' (1 <= n <= 64); 'fortran_order': False; 'shape' one dimension (rows,); and exactly
/// rows records after the header. InputError naming `file` and what was expected otherwise;
/// nothing outside `bytes` is read and no size overflows.
NpyLayout read_npy_layout(const std::string& bytes, const std::string& file, const std::string& half_written);

/// The time series as the CSV text pcsim run writes it (csv_header_line and write_csv_row):
/// the same bytes as the run's timeseries.csv.
std::string time_series_csv(const TimeSeries& series);

}  // namespace pcsim::sim
