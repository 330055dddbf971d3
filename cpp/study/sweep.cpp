// The sweep engine: threads, MPI ranks, the resumable sweep.csv.
#include "study/sweep.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <utility>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "common/files.hpp"
#include "common/parallel.hpp"
#include "common/version.hpp"
#include "sim/run.hpp"
#include "study/progress.hpp"
#include "study/table.hpp"

namespace pcsim::study {

namespace {

std::string errno_text(const std::string& what, const std::filesystem::path& p) {
  return errno_message(what, p);
}

/// Writes all of `data` to fd; "" or the reason.
std::string write_all(int fd, const std::string& data, const std::filesystem::path& p) {
  std::size_t off = 0;
  while (off < data.size()) {
    const ssize_t n = ::write(fd, data.data() + off, data.size() - off);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno_text("cannot write", p);
    }
    off += static_cast<std::size_t>(n);
  }
  return "";
}

/// Replaces `file` by `content` atomically and durably (common/files.hpp). "" or the reason.
std::string replace_file(const std::filesystem::path& file, const std::string& content) {
  try {
    write_file_atomically(file, content, true);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

/// The append-only journal of a sweep in progress (rank 0).
class Journal {
 public:
  ~Journal() {
    if (fd_ >= 0) ::close(fd_);
  }

  /// Reads an earlier sweep.csv (keeping its good rows: grid rows into `lines`, others into
  /// `foreign`), rewrites it clean and opens it for appending. "" or the reason.
  std::string open(const std::filesystem::path& csv, const std::string& header_line,
                   const sim::Grid& grid, std::vector<std::optional<std::string>>& lines,
                   std::vector<std::string>& foreign, SweepReport& report) {
    csv_ = csv;
    std::error_code ec;
    std::filesystem::create_directories(csv.parent_path().empty() ? "." : csv.parent_path(), ec);
    if (ec) return "cannot create directory " + csv.parent_path().string() + ": " + ec.message();
    std::string old;
    if (std::filesystem::exists(csv)) {
      std::ifstream in(csv, std::ios::binary);
      if (!in) return errno_text("cannot read", csv);
      std::ostringstream ss;
      ss << in.rdbuf();
      old = ss.str();
    }
    std::string kept = header_line + "\n";
    std::size_t pos = old.find('\n');
    if (pos != std::string::npos) {
      if (old.compare(0, pos, header_line) != 0)
        return csv.string() + " holds another sweep (its columns differ from this one's); "
               "use another --out directory or remove the file";
      std::unordered_map<std::string, std::size_t> index_of;
      index_of.reserve(grid.size());
      const std::size_t naxes = grid.axes().size();
      for (std::size_t i = 0; i < grid.size(); ++i) index_of.emplace(csv_line(grid.texts(i)), i);
      const std::size_t ncols = parse_csv_line(header_line)->size();
      for (std::size_t start = pos + 1; start < old.size();) {
        const std::size_t end = old.find('\n', start);
        if (end == std::string::npos) {  // torn last line: the point was in flight
          ++report.dropped;
          break;
        }
        const std::string line = old.substr(start, end - start);
        start = end + 1;
        const auto fields = parse_csv_line(line);
        if (!fields || fields->size() != ncols) {
          ++report.dropped;
          continue;
        }
        const std::vector<std::string> key(fields->begin(), fields->begin() + naxes);
        const auto it = index_of.find(csv_line(key));
        if (it == index_of.end()) {
          foreign.push_back(line);
        } else if (!lines[it->second]) {
          lines[it->second] = line;
          ++report.skipped;
        } else {
          continue;  // a duplicate of a point already kept
        }
        kept += line + "\n";
      }
    } else if (!old.empty()) {
      ++report.dropped;  // only a torn header
    }
    report.foreign = foreign.size();
    if (std::string err = replace_file(csv, kept); !err.empty()) return err;
    fd_ = ::open(csv.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0) return errno_text("cannot open", csv);
    return "";
  }

  /// Appends one complete line and makes it durable. "" or the reason.
  std::string append(const std::string& line) {
    std::string err = write_all(fd_, line + "\n", csv_);
    if (err.empty() && ::fdatasync(fd_) != 0) err = errno_text("cannot fsync", csv_);
    return err;
  }

  /// Rewrites the whole table in grid order. "" or the reason.
  std::string finish(const std::string& header_line,
                     const std::vector<std::optional<std::string>>& lines,
                     const std::vector<std::string>& foreign) {
    std::string all = header_line + "\n";
    for (const auto& l : lines)
      if (l) all += *l + "\n";
    for (const auto& l : foreign) all += l + "\n";
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    return replace_file(csv_, all);
  }

 private:
  std::filesystem::path csv_;
  int fd_ = -1;
};

/// Finished rows handed from worker threads to the thread that writes or sends them.
class RowQueue {
 public:
  void push(std::size_t index, std::string line) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      rows_.emplace_back(index, std::move(line));
    }
    ready_.notify_one();
  }
  std::optional<std::pair<std::size_t, std::string>> pop(std::chrono::milliseconds wait) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!ready_.wait_for(lock, wait, [&] { return !rows_.empty(); })) return std::nullopt;
    auto row = std::move(rows_.front());
    rows_.pop_front();
    return row;
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::pair<std::size_t, std::string>> rows_;
};

std::string join_numbers(const std::vector<std::size_t>& v) {
  std::string s;
  for (std::size_t x : v) s += std::to_string(x) + " ";
  return s;
}

std::vector<std::size_t> split_numbers(const std::string& s) {
  std::vector<std::size_t> v;
  std::istringstream in(s);
  std::size_t x = 0;
  while (in >> x) v.push_back(x);
  return v;
}

// The first lines in which two key texts differ, for the refusal message.
std::string key_differences(const std::string& old_key, const std::string& new_key) {
  std::istringstream a(old_key), b(new_key);
  std::vector<std::string> la, lb;
  for (std::string l; std::getline(a, l);) la.push_back(l);
  for (std::string l; std::getline(b, l);) lb.push_back(l);
  std::string out;
  int shown = 0;
  for (const auto& l : lb) {
    if (std::find(la.begin(), la.end(), l) != la.end()) continue;
    if (shown++ == 3) {
      out += "; ...";
      break;
    }
    out += (out.empty() ? "" : "; ") + std::string("now '") + l + "'";
  }
  for (const auto& l : la) {
    if (shown > 3) break;
    if (std::find(lb.begin(), lb.end(), l) != lb.end()) continue;
    if (shown++ == 3) {
      out += "; ...";
      break;
    }
    out += (out.empty() ? "" : "; ") + std::string("was '") + l + "'";
  }
  return out;
}

/// Checks (or records) the journal key of out_dir. "" or the reason to refuse.
std::string check_key(const std::filesystem::path& dir, const std::string& key, bool restart) {
  const auto csv = dir / "sweep.csv", key_file = dir / "sweep.key";
  std::error_code ec;
  const bool have_csv = std::filesystem::exists(csv, ec);
  std::string old;
  const bool have_key = std::filesystem::exists(key_file, ec);
  if (have_key) {
    std::ifstream in(key_file, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    old = ss.str();
  }
  if (have_csv && old != key) {
    if (!restart)
      return csv.string() + " holds another sweep's rows, computed for another case, model or "
             "pcsim version (" +
             (have_key ? key_differences(old, key) : std::string("it has no sweep.key")) +
             "); its rows are not reused: run with --restart to discard them and compute every "
             "point, or use another --out";
    std::filesystem::remove(csv, ec);
    if (ec) return "cannot remove " + csv.string() + ": " + ec.message();
  }
  if (old != key) {
    try {
      write_file_atomically(key_file, key, true);
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  return "";
}

}  // namespace

std::string sweep_key(const sim::Case& base, const sim::Grid& grid) {
  sim::Case c = base;
  for (const auto& a : grid.axes()) {
    const auto dot = a.key.rfind('.');
    toml::table* sec = dot == std::string::npos
                           ? &c.table
                           : c.table.at_path(a.key.substr(0, dot)).as_table();
    if (sec) sec->erase(dot == std::string::npos ? a.key : a.key.substr(dot + 1));
  }
  std::string key = "# pcsim sweep key: the rows of sweep.csv in this directory were computed for\n";
  key += "pcsim " + std::string(version_string()) + "\n";
  key += "model " + base.model->fingerprint() + "\n";
  key += "varied";
  for (const auto& a : grid.axes()) key += " " + a.key;
  key += "\n";
  key += sim::to_toml(c, "the effective case without the varied keys");
  return key;
}

Runner case_runner() {
  return [](const sim::Case& c) { return sim::run_case(c, sim::RunOptions{}); };
}

std::vector<std::string> sweep_header(const sim::Case& base, const sim::Grid& grid) {
  std::vector<std::string> h;
  for (const auto& a : grid.axes()) h.push_back(a.key);
  for (const auto& c : summary_columns(base)) h.push_back(c);
  h.push_back(kStatusColumn);
  h.push_back(kErrorColumn);
  return h;
}

std::vector<std::string> sweep_row(const sim::Case& base, const sim::Grid& grid, std::size_t i,
                                   const Runner& runner) {
  std::vector<std::string> row = grid.texts(i);
  std::vector<std::string> fields;
  std::string error;
  const std::vector<std::string> columns = summary_columns(base);
  try {
    const sim::Case c = grid.point_case(base, i);
    fields = flatten_summary(runner(c), c, columns);
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "unknown error";
  } catch (...) {
    error = "unknown error";
  }
  if (!error.empty()) fields.assign(columns.size(), "");
  row.insert(row.end(), fields.begin(), fields.end());
  row.push_back(error.empty() ? "ok" : "error");
  row.push_back(error);
  return row;
}

SweepReport run_sweep(const sim::Case& base, const sim::Grid& grid, const Runner& runner,
                      const SweepOptions& options) {
  const int rank = options.cluster ? options.cluster->rank() : 0;
  const int size = options.cluster ? options.cluster->size() : 1;
  SweepReport report;
  report.csv = options.out_dir / "sweep.csv";
  report.points = grid.size();
  const std::string header_line = csv_line(sweep_header(base, grid));
  const std::size_t n_summary = summary_columns(base).size();

  // Rank 0 locks the directory, checks the journal key, reads the earlier file and decides
  // what is pending; the others are told.
  std::unique_ptr<OwnedDirectory> owned;  // locked and marked for options.owner
  Journal journal;
  std::vector<std::optional<std::string>> lines;
  std::vector<std::string> foreign;
  std::vector<std::size_t> pending;
  if (rank == 0) {
    lines.resize(grid.size());
    try {
      owned = std::make_unique<OwnedDirectory>(options.out_dir, options.owner);
    } catch (const std::exception& e) {
      report.error = e.what();
    }
    if (report.error.empty()) report.error = check_key(options.out_dir, sweep_key(base, grid), options.restart);
    if (report.error.empty())
      report.error = journal.open(report.csv, header_line, grid, lines, foreign, report);
    for (std::size_t i = 0; i < grid.size(); ++i)
      if (!lines[i]) pending.push_back(i);
  }
  if (size > 1) {
    report.error = options.cluster->broadcast(report.error);
    pending = split_numbers(options.cluster->broadcast(join_numbers(pending)));
  }
  if (!report.error.empty()) {
    report.ok = false;
    return report;
  }

  std::vector<std::size_t> mine;
  for (std::size_t k = static_cast<std::size_t>(rank); k < pending.size();
       k += static_cast<std::size_t>(size))
    mine.push_back(pending[k]);

  RowQueue queue;
  Workers workers(mine.size(), options.jobs, [&](std::size_t k) {
    queue.push(mine[k], csv_line(sweep_row(base, grid, mine[k], runner)));
  });

  // This thread writes (rank 0) or forwards (other ranks) every finished row.
  Progress progress(grid.size(), grid.size() - pending.size(), options.progress && rank == 0);
  const std::size_t expected = rank == 0 ? pending.size() : mine.size();
  std::string io_error;
  auto take = [&](std::size_t index, std::string line) {
    if (rank != 0) {
      options.cluster->send_row(index, line);
      return;
    }
    if (io_error.empty()) io_error = journal.append(line);
    lines[index] = std::move(line);
    progress.tick();
  };
  for (std::size_t got = 0; got < expected;) {
    if (auto row = queue.pop(std::chrono::milliseconds(size > 1 ? 2 : 200))) {
      take(row->first, std::move(row->second));
      ++got;
    }
    if (rank == 0 && size > 1)
      while (auto remote = options.cluster->poll_row()) {
        take(remote->first, std::move(remote->second));
        ++got;
      }
  }
  workers.join();
  progress.finish();

  if (rank == 0) {
    std::string err = journal.finish(header_line, lines, foreign);
    if (io_error.empty()) io_error = err;
    const std::size_t status_col = grid.axes().size() + n_summary;
    for (const auto& l : lines)
      if (l) {
        const auto f = parse_csv_line(*l);
        if (f && f->size() > status_col && (*f)[status_col] == "error") ++report.failed;
      }
  }
  report.ran = pending.size();
  if (size > 1) {
    io_error = options.cluster->broadcast(io_error);
    report.failed = std::stoul(options.cluster->broadcast(std::to_string(report.failed)));
    report.skipped = grid.size() - pending.size();
  }
  report.error = io_error;
  report.ok = io_error.empty();
  return report;
}

}  // namespace pcsim::study
