#include "common/files.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <system_error>
#include <vector>

#include <signal.h>
#include <sys/stat.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "common/error.hpp"

namespace pcsim {

namespace fs = std::filesystem;

namespace {

std::string unique_suffix() {
  static std::atomic<unsigned> counter{0};
  return std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

void write_all(int fd, const std::string& data, const fs::path& p) {
  std::size_t off = 0;
  while (off < data.size()) {
    const ssize_t n = ::write(fd, data.data() + off, data.size() - off);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError(errno_message("cannot write", p));
    }
    off += static_cast<std::size_t>(n);
  }
}

void fsync_directory(const fs::path& dir) {
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);  // best effort: makes a rename durable
    ::close(dfd);
  }
}

void write_new_file(const fs::path& file, const std::string& content, bool durable) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(errno_message("cannot create", file));
  try {
    write_all(fd, content, file);
    if (durable && ::fsync(fd) != 0) throw IoError(errno_message("cannot fsync", file));
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw IoError(errno_message("cannot write", file));
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool all_digits(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

/// `.NAME.tmpPID-N`: write_file_atomically's temporary, `.NAME.partPID`: pcsim plot's.
bool is_temporary(const std::string& name) {
  if (name.size() < 2 || name[0] != '.') return false;
  for (const char* tag : {".tmp", ".part"}) {
    const auto at = name.rfind(tag);
    if (at == std::string::npos || at == 0) continue;
    std::string rest = name.substr(at + std::strlen(tag));
    const auto dash = rest.find('-');
    if (dash != std::string::npos) {
      if (!all_digits(rest.substr(dash + 1))) continue;
      rest = rest.substr(0, dash);
    }
    if (all_digits(rest)) return true;
  }
  return false;
}

/// "" or the reason why `dir` cannot be any command's output directory: the root, a path
/// ending in . or .., the current directory or one of its parents.
std::string unusable_reason(const fs::path& dir) {
  const std::string leaf = dir.filename().string();
  if (leaf.empty() || leaf == "." || leaf == "..")
    return "it names no directory of its own (a path ending in /, . or ..)";
  // Beside it live .<name>.lock and .<name>.staging-<pid>-<n>.old: all within NAME_MAX (255).
  if (leaf.size() > kMaxOutputLeafBytes)
    return "its last component has " + std::to_string(leaf.size()) + " bytes, more than " +
           std::to_string(kMaxOutputLeafBytes) + " (pcsim keeps hidden files named after it beside it)";
  std::error_code ec;
  const fs::path real = fs::canonical(dir, ec);
  if (ec) return "";  // absent: created new
  const fs::path cwd = fs::canonical(fs::current_path(ec), ec);
  if (ec) return "";
  auto c = cwd.begin();
  for (auto r = real.begin(); r != real.end(); ++r, ++c)
    if (c == cwd.end() || *c != *r) return "";
  return "it is the current directory or one of its parents";
}

/// Throws InputError unless `dir` may be used by `command` (see kOwnerMarker).
void check_owner(const fs::path& dir, const std::string& command, bool replaces) {
  if (const std::string why = unusable_reason(dir); !why.empty())
    throw InputError("output directory " + dir.string() + " cannot be used: " + why +
                     "; give pcsim a directory of its own with --out");
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(dir, ec);
  if (!fs::exists(link)) return;
  if (replaces && fs::is_symlink(link))
    throw InputError("output directory " + dir.string() + " is a symbolic link; pcsim replaces its "
                     "output directory as a whole, so give the directory it points to, or another --out");
  if (!fs::is_directory(dir, ec))
    throw InputError("output directory " + dir.string() + " exists and is not a directory; choose another --out");
  const std::string owner = directory_owner(dir);
  if (!owner.empty() && owner != command)
    throw InputError("output directory " + dir.string() + " belongs to `pcsim " + owner + "` (its " +
                     kOwnerMarker + " says so); `pcsim " + command +
                     "` does not write into another command's directory: choose another --out");
  std::vector<std::string> foreign;
  std::size_t n_foreign = 0;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name == kOwnerMarker) continue;
    const bool ours = pcsim_writes(command, name);
    // pcsim writes files, never directories or links: a link named like one of its files
    // (optimize.csv -> a user's file) would make pcsim write through it.
    if (ours && !fs::is_regular_file(it->symlink_status(ec)))
      throw InputError("output directory " + dir.string() + " holds " + name +
                       ", which is not a regular file, where pcsim " + command +
                       " writes a file of that name; remove it or choose another --out");
    if (!ours && n_foreign++ < 3) foreign.push_back(name);
  }
  if (ec) throw IoError("cannot read the directory " + dir.string() + ": " + ec.message());
  if (n_foreign == 0 || (!owner.empty() && !replaces)) return;
  std::string list;
  for (const auto& f : foreign) list += (list.empty() ? "" : ", ") + f;
  if (n_foreign > foreign.size()) list += " and " + std::to_string(n_foreign - foreign.size()) + " more";
  if (owner.empty())
    throw InputError("output directory " + dir.string() + " exists and is not a pcsim output "
                     "directory of `pcsim " + command + "` (it has no " + kOwnerMarker +
                     " marker and holds " + list + ", which pcsim " + command +
                     " does not write); pcsim never writes into or replaces a directory it did not "
                     "make: choose another --out");
  throw InputError("output directory " + dir.string() + " holds " + list + ", which pcsim " + command +
                   " did not write; pcsim replaces its output directory as a whole and never deletes a "
                   "file it did not write: move the file(s) out or choose another --out");
}

std::string marker_text(const std::string& command) {
  return command + "\n# This directory is the output of `pcsim " + command +
         "`; pcsim writes here only as this command. Do not keep other files here.\n";
}

fs::path normalized(fs::path dir) {
  dir = dir.lexically_normal();
  if (dir.filename().empty() && dir.has_parent_path() && dir != dir.root_path()) dir = dir.parent_path();
  return dir;
}

/// Removes the staging directories `.<leaf>.staging-PID-N[.old]` beside `dir` that runs killed
/// earlier left: only when their process is gone and they carry pcsim's marker (so a PID reused
/// by another process, or a directory pcsim did not make, is left alone).
void remove_stale_staging(const fs::path& parent, const std::string& leaf) {
  const std::string prefix = "." + leaf + ".staging-";
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    std::string rest = name.substr(prefix.size());
    if (ends_with(rest, ".old")) rest.resize(rest.size() - 4);
    const auto dash = rest.find('-');
    if (dash == std::string::npos || !all_digits(rest.substr(0, dash)) ||
        !all_digits(rest.substr(dash + 1)) || dash > 9)
      continue;
    const long pid = std::stol(rest.substr(0, dash));
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or unknown
    std::error_code e2;
    if (!fs::is_directory(fs::symlink_status(it->path(), e2))) continue;
    if (!fs::is_regular_file(fs::symlink_status(it->path() / kOwnerMarker, e2))) continue;
    stale.push_back(it->path());
  }
  for (const auto& p : stale) fs::remove_all(p, ec);
}

}  // namespace

std::string errno_message(const std::string& what, const fs::path& path) {
  return what + " " + path.string() + ": " + std::strerror(errno);
}

bool pcsim_writes(const std::string& command, const std::string& name) {
  if (is_temporary(name)) return true;
  auto one_of = [&](std::initializer_list<const char*> names) {
    for (const char* n : names)
      if (name == n) return true;
    return false;
  };
  // pcsim plot's figures, script and data (plots.csv: a timeseries.npy's rows as the text
  // gnuplot reads) live in the directory they plot.
  const bool plot = name == "plots.gp" || name == "plots.csv" || (ends_with(name, ".png") && name[0] != '.') ||
                    // the model it ran, and pcsim animate's page and video (issue 26)
                    name == "model.toml" || name == "animation.html" || name == "animation.mp4" ||
                    name == "animation.gif";
  if (command == "run") return plot || one_of({"summary.json", "timeseries.csv", "timeseries.npy", "events.csv"});
  if (command == "steady") return plot || one_of({"steady.json", "timeseries.csv", "timeseries.npy", "events.csv"});
  if (command == "response") return plot || one_of({"response.csv", "response.json"});
  if (command == "modes")
    return plot || one_of({"modes.json", "modes.csv", "modes_vary.csv", "modes_vary.json"});
  const bool sweep = one_of({"sweep.csv", "sweep.key", ".sweep.lock"});
  if (command == "sweep") return sweep;
  if (command == "incline")
    return sweep || one_of({"incline.csv", "incline.gp", "incline.png", "gnuplot.log"});
  if (command == "optimize") return one_of({"optimize.csv", "best.toml"});
  return false;
}

std::string directory_owner(const fs::path& dir) {
  const fs::path marker = dir / kOwnerMarker;
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(marker, ec))) return "";
  std::ifstream in(marker, std::ios::binary);
  std::string line;
  char c;
  while (line.size() < 64 && in.get(c) && c != '\n') line += c;
  while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
  return line.empty() ? std::string("an unknown command") : line;
}

DirectoryLock::DirectoryLock(const fs::path& dir_in) {
  const fs::path dir = normalized(dir_in);
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  file_ = parent / ("." + dir.filename().string() + ".lock");
  for (int attempt = 0;; ++attempt) {
    fd_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0) throw IoError(errno_message("cannot create the lock file", file_));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd_);
      fd_ = -1;
      if (err == EWOULDBLOCK)
        throw InputError("output directory " + dir.string() + " is in use by another pcsim run (lock " +
                         file_.string() + "); wait for it or choose another --out");
      errno = err;
      throw IoError(errno_message("cannot lock", file_));
    }
    // The holder before us unlinks the file before it unlocks: ours must still be the file
    // the path names, or we locked a file nobody else will ever see.
    struct stat held{}, named{};
    if (::fstat(fd_, &held) == 0 && ::stat(file_.c_str(), &named) == 0 &&
        held.st_dev == named.st_dev && held.st_ino == named.st_ino)
      return;
    ::close(fd_);
    fd_ = -1;
    if (attempt > 100) throw IoError("cannot lock " + file_.string() + ": it keeps being replaced");
  }
}

DirectoryLock::~DirectoryLock() {
  if (fd_ < 0) return;
  ::unlink(file_.c_str());  // while still holding the lock (see the constructor)
  ::close(fd_);
}

namespace {
// What every command's output directory starts with: a usable path, its parent made, and the
// lock beside it taken.
std::unique_ptr<DirectoryLock> lock_output_directory(const fs::path& dir) {
  if (const std::string why = unusable_reason(dir); !why.empty())
    throw InputError("output directory " + dir.string() + " cannot be used: " + why +
                     "; give pcsim a directory of its own with --out");
  std::error_code ec;
  const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) throw IoError("cannot create the output directory " + parent.string() + ": " + ec.message());
  return std::make_unique<DirectoryLock>(dir);
}
}  // namespace

OwnedDirectory::OwnedDirectory(const fs::path& dir, const std::string& command) : dir_(normalized(dir)) {
  lock_ = lock_output_directory(dir_);
  std::error_code ec;
  check_owner(dir_, command, false);
  fs::create_directory(dir_, ec);
  if (ec) throw IoError("cannot create the output directory " + dir_.string() + ": " + ec.message());
  if (directory_owner(dir_).empty()) write_file_atomically(dir_ / kOwnerMarker, marker_text(command), true);
}

void write_file_atomically(const fs::path& file, const std::string& content, bool durable) {
  const fs::path tmp = file.parent_path() / ("." + file.filename().string() + ".tmp" + unique_suffix());
  try {
    write_new_file(tmp, content, durable);
    if (std::rename(tmp.c_str(), file.c_str()) != 0)
      throw IoError(errno_message("cannot rename a temporary file to", file));
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  if (durable) fsync_directory(file.parent_path());
}

OutputDirectory::OutputDirectory(fs::path dir, const std::string& command)
    : dir_(normalized(std::move(dir))) {
  lock_ = lock_output_directory(dir_);
  std::error_code ec;
  const fs::path parent = dir_.has_parent_path() ? dir_.parent_path() : fs::path(".");
  check_owner(dir_, command, true);
  remove_stale_staging(parent, dir_.filename().string());
  staging_ = parent / ("." + dir_.filename().string() + ".staging-" + unique_suffix());
  fs::create_directory(staging_, ec);
  if (ec) {
    const std::string msg = "cannot create " + staging_.string() + ": " + ec.message();
    staging_.clear();
    throw IoError(msg);
  }
  // The marker first: a staging directory left by a killed run is recognised as pcsim's.
  try {
    write_new_file(staging_ / kOwnerMarker, marker_text(command), false);
  } catch (...) {
    fs::remove_all(staging_, ec);
    throw;
  }
}

OutputDirectory::~OutputDirectory() {
  std::error_code ec;
  if (!staging_.empty()) fs::remove_all(staging_, ec);
  lock_.reset();  // unlinks the lock file and releases the lock
}

void OutputDirectory::write(const std::string& name, const std::string& content) {
  if (committed_) throw IoError("output directory " + dir_.string() + " already committed");
  const fs::path p = staging_ / name;
  write_new_file(p, content, false);
  unsynced_.push_back(p);  // made durable by commit(), before the directory is swapped in
#ifdef __linux__
  // Start the write-back now (asynchronously), so that commit()'s fsync finds the data written.
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd >= 0) {
    ::sync_file_range(fd, 0, 0, SYNC_FILE_RANGE_WRITE);
    ::close(fd);
  }
#endif
}

OutputStream::OutputStream(OutputStream&& o) noexcept
    : fd_(o.fd_), path_(std::move(o.path_)), buffer_(std::move(o.buffer_)) {
  o.fd_ = -1;
}

OutputStream& OutputStream::operator=(OutputStream&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    path_ = std::move(o.path_);
    buffer_ = std::move(o.buffer_);
    o.fd_ = -1;
  }
  return *this;
}

OutputStream::~OutputStream() {
  if (fd_ >= 0) ::close(fd_);
}

void OutputStream::flush() {
  if (fd_ < 0) return;
  write_all(fd_, buffer_, path_);
#ifdef __linux__
  // Start the write-back of what was just written (asynchronously): close()'s fsync then finds
  // most of the file on its way to the disk already.
  ::sync_file_range(fd_, 0, 0, SYNC_FILE_RANGE_WRITE);
#endif
  buffer_.clear();
}

void OutputStream::rewrite(std::size_t offset, const std::string& bytes) {
  if (fd_ < 0) return;
  flush();
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
    if (w < 0) {
      if (errno == EINTR) continue;
      throw IoError(errno_message("cannot write", path_));
    }
    done += static_cast<std::size_t>(w);
  }
}

void OutputStream::close() {
  if (fd_ < 0) return;
  flush();
  const int fd = fd_;
  fd_ = -1;
  if (::fsync(fd) != 0) {
    const std::string msg = errno_message("cannot fsync", path_);
    ::close(fd);
    throw IoError(msg);
  }
  if (::close(fd) != 0) throw IoError(errno_message("cannot write", path_));
}

OutputStream OutputDirectory::open(const std::string& name) {
  const fs::path p = staging_ / name;
  const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(errno_message("cannot create", p));
  return OutputStream(fd, p);
}

void OutputDirectory::commit() {
  std::error_code ec;
  // The files of write() first (Linux fsyncs a file through any descriptor of it).
  for (const fs::path& p : unsynced_) {
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(errno_message("cannot reopen", p));
    if (::fsync(fd) != 0) {
      const std::string msg = errno_message("cannot fsync", p);
      ::close(fd);
      throw IoError(msg);
    }
    ::close(fd);
  }
  unsynced_.clear();
  fsync_directory(staging_);
  if (!fs::exists(dir_, ec)) {
    if (std::rename(staging_.c_str(), dir_.c_str()) != 0)
      throw IoError(errno_message("cannot move the results into", dir_));
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
      throw IoError(errno_message("cannot move the results into", dir_));
    // No atomic exchange on this file system: move the old directory aside, then the new one
    // in (a reader may find the directory missing for an instant, never mixed).
    const fs::path old = staging_.string() + ".old";
    if (std::rename(dir_.c_str(), old.c_str()) != 0)
      throw IoError(errno_message("cannot move the previous results aside in", dir_));
    if (std::rename(staging_.c_str(), dir_.c_str()) != 0) {
      const std::string msg = errno_message("cannot move the results into", dir_);
      std::rename(old.c_str(), dir_.c_str());
      throw IoError(msg);
    }
    staging_ = old;
  }
  // staging_ now names the previous content (or nothing): remove it.
  fs::remove_all(staging_, ec);
  staging_.clear();
  committed_ = true;
  fsync_directory(dir_.has_parent_path() ? dir_.parent_path() : fs::path("."));
}

}  // namespace pcsim
