// Output files written whole or not at all: atomic replacement of one file, and the output
// directory of a run, locked against a second writer and committed as one (every file of the
// run appears together, or none does).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace pcsim {

/// An output file or directory could not be written; the message names the path and the
/// system's reason (errno text). The CLI exits with status 1.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// "<what> <path>: <strerror(errno)>".
std::string errno_message(const std::string& what, const std::filesystem::path& path);

/// Replaces `file` by `content` atomically: a temporary file in the same directory, written
/// completely (and fsync'ed when durable), then renamed over `file` (and the directory fsync'ed
/// when durable). Throws IoError naming the path and the reason; leaves no temporary behind.
void write_file_atomically(const std::filesystem::path& file, const std::string& content,
                           bool durable = false);

/// The output directory of one run, as a transaction:
/// - the constructor takes an exclusive lock (flock on the hidden sibling file
///   `<parent>/.<name>.lock`), so a second pcsim writing to the same directory is refused at
///   once with InputError; it checks that the directory is absent, empty or a pcsim output
///   directory (it holds a summary.json, steady.json or response.json), so that pcsim never
///   replaces a user's directory; and it creates a staging directory beside it;
/// - write() puts files into the staging directory;
/// - commit() swaps the staging directory with the target in one atomic step
///   (renameat2 RENAME_EXCHANGE; two renames where the file system lacks it) and removes the
///   old content: a reader sees the previous run's files or this run's, never a mix, and no
///   stale file of an earlier run (e.g. an old plot) survives;
/// - without commit() (an exception, a failed run) the destructor removes the staging
///   directory and the target stays as it was.
/// A file being written piecewise into an output directory's staging area (buffered; call
/// close() to flush and check for errors; the destructor closes without checking).
class OutputStream {
 public:
  OutputStream() = default;
  OutputStream(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {}
  OutputStream(OutputStream&& o) noexcept;
  OutputStream& operator=(OutputStream&& o) noexcept;
  ~OutputStream();
  bool is_open() const { return fd_ >= 0; }
  /// The buffer to append to; flushed to the file when it grows past 1 MB (throws IoError).
  std::string& buffer() { return buffer_; }
  void maybe_flush() {
    if (buffer_.size() >= (1u << 20)) flush();
  }
  void flush();
  /// Flushes, fsyncs and closes; throws IoError naming the file and the reason.
  void close();

 private:
  int fd_ = -1;
  std::filesystem::path path_;
  std::string buffer_;
};

class OutputDirectory {
 public:
  explicit OutputDirectory(std::filesystem::path dir);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  const std::filesystem::path& path() const { return dir_; }
  /// Writes one file into the staging directory; throws IoError.
  void write(const std::string& name, const std::string& content);
  /// Opens one file in the staging directory for piecewise writing; throws IoError.
  OutputStream open(const std::string& name);
  /// Makes the staged files the directory's content; throws IoError.
  void commit();

 private:
  std::filesystem::path dir_, staging_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

}  // namespace pcsim
