#include "sim/row_writer.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"

namespace pcsim::sim {

namespace {
constexpr std::size_t kBlockRows = 512;
#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "timeseries.npy is written as little-endian float64 ('<f8'): a big-endian host needs a byte swap"
#endif
}

std::string npy_header(const std::vector<std::string>& names, int label_columns, int label_width,
                       unsigned long long rows) {
  std::string dict = "{'descr': [";
  const int n = static_cast<int>(names.size());
  for (int i = 0; i < n; ++i) {
    std::string name;  // a Python string literal's text (column names are identifiers anyway)
    for (char ch : names[static_cast<std::size_t>(i)]) {
      if (ch == '\\' || ch == '\'') name += '\\';
      name += ch;
    }
    dict += (i ? ", ('" : "('") + name + "', ";
    dict += i >= n - label_columns ? "'|S" + std::to_string(label_width) + "')" : "'<f8')";
  }
  std::string count = std::to_string(rows);
  count.insert(0, 20 - count.size(), ' ');  // fixed width: the final count rewrites it in place
  dict += "], 'fortran_order': False, 'shape': (" + count + ",), }";
  // magic, version, header length; the whole header a multiple of 64 bytes, ending in '\n'.
  const bool v2 = dict.size() + 1 + 10 > 65535;
  const std::size_t prefix = v2 ? 12 : 10;
  std::size_t total = prefix + dict.size() + 1;
  const std::size_t padded = (total + 63) / 64 * 64;
  dict.append(padded - total, ' ');
  dict += '\n';
  std::string h = "\x93NUMPY";
  h += static_cast<char>(v2 ? 2 : 1);
  h += '\0';
  const std::size_t len = dict.size();
  h += static_cast<char>(len & 0xff);
  h += static_cast<char>((len >> 8) & 0xff);
  if (v2) {
    h += static_cast<char>((len >> 16) & 0xff);
    h += static_cast<char>((len >> 24) & 0xff);
  }
  return h + dict;
}

std::string csv_header_line(const std::vector<std::string>& columns) {
  std::string h;
  for (std::size_t i = 0; i < columns.size(); ++i) h += (i ? "," : "") + columns[i];
  return h + '\n';
}

std::size_t csv_row_room(int columns, int label_columns, const std::vector<std::string>& labels) {
  std::size_t room = static_cast<std::size_t>(columns) * (kMaxNumberChars + 1) + 1;
  for (const auto& l : labels) room += static_cast<std::size_t>(label_columns) * l.size();
  return room;
}

char* write_csv_row(char* p, const double* row, int columns, int label_columns,
                    const std::vector<std::string>& labels) {
  const int numbers = columns - label_columns;
  for (int j = 0; j < columns; ++j) {
    if (j) *p++ = ',';
    if (j >= numbers) {
      const std::string& l = labels.at(static_cast<std::size_t>(row[j]));
      p = std::copy(l.begin(), l.end(), p);
    } else {
      p = write_csv_number(p, row[j]);  // an undefined value (f* in flight) is an empty field
    }
  }
  *p++ = '\n';
  return p;
}

RowWriter::RowWriter(OutputStream& out, int columns, int label_columns, std::vector<std::string> labels)
    : out_(out), columns_(columns), label_columns_(label_columns), labels_(std::move(labels)) {
  block_.reserve(kBlockRows * static_cast<std::size_t>(columns));
  thread_ = std::thread([this] { work(); });
}

RowWriter::RowWriter(OutputStream& out, int columns, int label_columns, std::vector<std::string> labels, Npy npy)
    : out_(out), columns_(columns), label_columns_(label_columns), labels_(std::move(labels)), npy_(true),
      names_(std::move(npy.names)) {
  for (const auto& l : labels_) label_width_ = std::max(label_width_, static_cast<int>(l.size()));
  out_.buffer() += npy_header(names_, label_columns_, label_width_, 0);
  block_.reserve(kBlockRows * static_cast<std::size_t>(columns));
  thread_ = std::thread([this] { work(); });
}

RowWriter::~RowWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void RowWriter::add(const double* row) {
  block_.insert(block_.end(), row, row + columns_);
  if (block_.size() >= kBlockRows * static_cast<std::size_t>(columns_)) flush_block();
}

void RowWriter::flush_block() {
  if (block_.empty()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(block_));
  }
  cv_.notify_one();
  block_ = std::vector<double>();
  block_.reserve(kBlockRows * static_cast<std::size_t>(columns_));
}

void RowWriter::work() {
  for (;;) {
    std::vector<double> rows;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return done_ || !queue_.empty(); });
      if (queue_.empty()) return;  // done, nothing left
      rows = std::move(queue_.front());
      queue_.pop_front();
    }
    if (error_) continue;  // drain after a failure
    try {
      if (npy_) {
        // Each number's 8 bytes as they are (little-endian, checked at compile time), each
        // label's text zero-padded to its field.
        std::string& bytes = out_.buffer();
        const int numbers = columns_ - label_columns_;
        for (std::size_t i = 0; i < rows.size(); i += static_cast<std::size_t>(columns_)) {
          const double* row = rows.data() + i;
          bytes.append(reinterpret_cast<const char*>(row), static_cast<std::size_t>(numbers) * sizeof(double));
          for (int j = numbers; j < columns_; ++j) {
            const std::string& l = labels_.at(static_cast<std::size_t>(row[j]));
            bytes.append(l);
            bytes.append(static_cast<std::size_t>(label_width_) - l.size(), '\0');
          }
          ++rows_written_;
        }
        out_.maybe_flush();
        continue;
      }
      std::string& text = out_.buffer();
      // A row is formatted into line_ (room for every field at its longest) and appended whole.
      const std::size_t room = csv_row_room(columns_, label_columns_, labels_);
      if (line_.size() < room) line_.resize(room);
      for (std::size_t i = 0; i < rows.size(); i += static_cast<std::size_t>(columns_))
        text.append(line_.data(), write_csv_row(line_.data(), rows.data() + i, columns_, label_columns_, labels_));
      out_.maybe_flush();
    } catch (...) {
      error_ = std::current_exception();
    }
  }
}

void RowWriter::finish() {
  flush_block();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(error_);
  if (npy_) out_.rewrite(0, npy_header(names_, label_columns_, label_width_, rows_written_));
  out_.close();
}

}  // namespace pcsim::sim
