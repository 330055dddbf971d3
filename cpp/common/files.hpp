// Output files written whole or not at all: atomic replacement of one file, and the output
// directory of a run, locked against a second writer and committed as one (every file of the
// run appears together, or none does).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace pcsim {

/// "<what> <path>: <strerror(errno)>".
std::string errno_message(const std::string& what, const std::filesystem::path& path);

/// Replaces `file` by `content` atomically: a temporary file in the same directory, written
/// completely (and fsync'ed when durable), then renamed over `file` (and the directory fsync'ed
/// when durable). Throws IoError naming the path and the reason; leaves no temporary behind.
void write_file_atomically(const std::filesystem::path& file, const std::string& content,
                           bool durable = false);

/// Output directories belong to the command that made them. Each one holds the marker file
/// `.pcsim-output`, whose first line names its owner: run, steady, response, sweep, incline or
/// optimize. A command refuses (InputError, exit 2) a directory that
/// - is owned by another command (the message names the directory and its owner);
/// - has no marker (a user's directory, or one written before markers existed) and holds a
///   file the command does not write (pcsim_writes), e.g. a sweep's journal in a run's --out;
/// - is the current directory or one of its parents, the root, or a path ending in . or ..;
/// - (replacing commands: run, steady, response) holds any file the command does not write,
///   marked or not, since the directory is replaced whole and pcsim never deletes a file it did
///   not write; or is a symbolic link.
inline constexpr const char* kOwnerMarker = ".pcsim-output";

/// The longest last component of an output directory's path, in bytes: its lock and staging
/// siblings (.<name>.staging-<pid>-<n>.old) must fit the file system's 255.
inline constexpr std::size_t kMaxOutputLeafBytes = 200;

/// True if `command` writes a file of this name into its output directory (its own files,
/// `pcsim plot`'s figures and script in run, steady and response directories, and pcsim's
/// temporaries `.NAME.tmpPID-N`).
bool pcsim_writes(const std::string& command, const std::string& file_name);

/// The owner named by dir's marker, or "" when it has none.
std::string directory_owner(const std::filesystem::path& dir);

/// An exclusive, non-blocking lock on a directory: flock on the hidden sibling file
/// `<parent>/.<name>.lock`, unlinked again when the lock is released (the lock file is re-checked
/// after flock to be the file the path names, so two processes never hold locks on different
/// files). A second holder is refused at once with InputError ("in use by another pcsim run").
class DirectoryLock {
 public:
  DirectoryLock() = default;
  explicit DirectoryLock(const std::filesystem::path& dir);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  std::filesystem::path file_;
  int fd_ = -1;
};

/// A directory that a command writes into in place (sweep, incline, optimize): checked and
/// locked as above, created when absent, and marked with the owner. The lock is held while the
/// object lives.
class OwnedDirectory {
 public:
  OwnedDirectory(const std::filesystem::path& dir, const std::string& command);
  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::unique_ptr<DirectoryLock> lock_;
};

/// The output directory of one run, as a transaction:
/// - the constructor takes the directory's lock (DirectoryLock), so a second pcsim writing to
///   the same directory is refused at once with InputError; it checks that the directory is
///   absent, empty or the `command`'s own output directory (see kOwnerMarker), so that pcsim
///   never replaces a user's directory or another command's; it removes the staging
///   directories that runs killed earlier left beside it (those whose process is gone and that
///   carry pcsim's marker), and it creates a staging directory beside it, marked for `command`;
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
  /// Flushes, then overwrites `bytes` at `offset` of the file (a header whose counts are known
  /// only at the end); throws IoError.
  void rewrite(std::size_t offset, const std::string& bytes);
  /// Flushes, fsyncs and closes; throws IoError naming the file and the reason.
  void close();

 private:
  int fd_ = -1;
  std::filesystem::path path_;
  std::string buffer_;
};

class OutputDirectory {
 public:
  OutputDirectory(std::filesystem::path dir, const std::string& command);
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
  std::unique_ptr<DirectoryLock> lock_;
  bool committed_ = false;
  /// Files written by write() whose fsync waits for commit(): one journal commit then makes
  /// them all durable, instead of one per file on the way (a run's model.toml, written before
  /// the integration, cost the paper's case 6.7 ms of wall time there).
  std::vector<std::filesystem::path> unsynced_;
};

}  // namespace pcsim
