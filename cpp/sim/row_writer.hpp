// The time-series writer of a run: rows of numbers handed over in blocks and formatted and
// written on a thread of their own, so the integration does not wait for the formatting
// (shortest round-trip decimals cost about as much as a third of the sieve's integration).
// The rows reach the file in the order given; an error of the writer (a full disk) is reported
// by finish().
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "common/files.hpp"

namespace pcsim::sim {

/// The bytes of a NumPy .npy file's header (format 1.0, or 2.0 when it exceeds 65535 bytes)
/// for `rows` records of the structured type with the fields `names`: little-endian float64,
/// then the last `label_columns` as zero-padded byte strings `label_width` long. The row count
/// is printed in a field of fixed width, so a header rewritten with the final count has the same
/// length. Names must be identifiers (column names are).
std::string npy_header(const std::vector<std::string>& names, int label_columns, int label_width,
                       unsigned long long rows);

/// The header line of timeseries.csv: the column names separated by commas, and '\n'.
std::string csv_header_line(const std::vector<std::string>& columns);

/// The room write_csv_row needs for a row of `columns` values whose last `label_columns` are
/// indices into `labels`.
std::size_t csv_row_room(int columns, int label_columns, const std::vector<std::string>& labels);

/// Writes one row of timeseries.csv at p (room: csv_row_room) and returns its end, after the
/// '\n': the numbers as the shortest decimals that read back to the same double (an undefined
/// value an empty field), the last `label_columns` values as the texts of `labels` they index.
char* write_csv_row(char* p, const double* row, int columns, int label_columns,
                    const std::vector<std::string>& labels);

class RowWriter {
 public:
  /// Writes to `out` (already holding the header) rows of `columns` numbers. With `labels`,
  /// the last `label_columns` values of each row are indices into `labels`, written as that
  /// text (the contacts' modes of a switching run).
  RowWriter(OutputStream& out, int columns, int label_columns = 0,
            std::vector<std::string> labels = {});
  /// The same rows as a NumPy .npy file (issue 23: a binary time series for large runs): the
  /// header (written here, with the final row count by finish()) names the fields `names`;
  /// each number is its 8 bytes (a NaN stays NaN), each label its text in a fixed-width field.
  struct Npy {
    std::vector<std::string> names;
  };
  RowWriter(OutputStream& out, int columns, int label_columns, std::vector<std::string> labels, Npy npy);
  ~RowWriter();  // joins the thread (after finish() or on an exception path)
  RowWriter(const RowWriter&) = delete;
  RowWriter& operator=(const RowWriter&) = delete;

  /// Appends one row (columns numbers).
  void add(const double* row);
  /// Writes what is left, stops the thread and closes the stream; throws IoError if any write
  /// failed.
  void finish();

 private:
  void flush_block();
  void work();

  OutputStream& out_;
  int columns_;
  int label_columns_ = 0;
  std::vector<std::string> labels_;
  std::vector<double> block_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::vector<double>> queue_;
  bool done_ = false;
  std::exception_ptr error_;
  std::vector<char> line_;  // the writer thread's row text
  bool npy_ = false;
  std::vector<std::string> names_;
  int label_width_ = 1;
  unsigned long long rows_written_ = 0;
  std::thread thread_;
};

}  // namespace pcsim::sim
