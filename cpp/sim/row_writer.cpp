#include "sim/row_writer.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"

namespace pcsim::sim {

namespace {
constexpr std::size_t kBlockRows = 512;
}

RowWriter::RowWriter(OutputStream& out, int columns, int label_columns, std::vector<std::string> labels)
    : out_(out), columns_(columns), label_columns_(label_columns), labels_(std::move(labels)) {
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
      std::string& text = out_.buffer();
      // A row is formatted into line_ (room for every field at its longest) and appended whole.
      std::size_t room = static_cast<std::size_t>(columns_) * (kMaxNumberChars + 1) + 1;
      for (const auto& l : labels_) room += static_cast<std::size_t>(label_columns_) * l.size();
      if (line_.size() < room) line_.resize(room);
      const int numbers = columns_ - label_columns_;
      for (std::size_t i = 0; i < rows.size(); i += static_cast<std::size_t>(columns_)) {
        const double* row = rows.data() + i;
        char* p = line_.data();
        for (int j = 0; j < columns_; ++j) {
          if (j) *p++ = ',';
          if (j >= numbers) {
            const std::string& l = labels_.at(static_cast<std::size_t>(row[j]));
            p = std::copy(l.begin(), l.end(), p);
          } else {
            p = write_csv_number(p, row[j]);  // an undefined value (f* in flight) is an empty field
          }
        }
        *p++ = '\n';
        text.append(line_.data(), p);
      }
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
  out_.close();
}

}  // namespace pcsim::sim
