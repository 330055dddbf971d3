#include "common/files.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

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

bool is_pcsim_output(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return true;
  if (!fs::is_directory(dir, ec)) return false;
  if (fs::is_empty(dir, ec)) return true;
  return fs::exists(dir / "summary.json", ec) || fs::exists(dir / "steady.json", ec) ||
         fs::exists(dir / "response.json", ec);
}

}  // namespace

std::string errno_message(const std::string& what, const fs::path& path) {
  return what + " " + path.string() + ": " + std::strerror(errno);
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

OutputDirectory::OutputDirectory(fs::path dir) : dir_(std::move(dir)) {
  if (dir_.filename().empty()) dir_ = dir_.parent_path();  // "out/x/" -> "out/x"
  std::error_code ec;
  const fs::path parent = dir_.has_parent_path() ? dir_.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) throw IoError("cannot create the output directory " + parent.string() + ": " + ec.message());
  const fs::path lock = parent / ("." + dir_.filename().string() + ".lock");
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw IoError(errno_message("cannot create the lock file", lock));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(lock_fd_);
    lock_fd_ = -1;
    if (err == EWOULDBLOCK)
      throw InputError("output directory " + dir_.string() +
                       " is in use by another pcsim run (lock " + lock.string() +
                       "); wait for it or choose another --out");
    errno = err;
    throw IoError(errno_message("cannot lock", lock));
  }
  if (!is_pcsim_output(dir_)) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw InputError("output directory " + dir_.string() +
                     " exists and is not a pcsim output directory (it is not empty and has no "
                     "summary.json, steady.json or response.json); pcsim replaces its output directory as a whole, so choose "
                     "another --out");
  }
  staging_ = parent / ("." + dir_.filename().string() + ".staging-" + unique_suffix());
  fs::create_directory(staging_, ec);
  if (ec) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw IoError("cannot create " + staging_.string() + ": " + ec.message());
  }
}

OutputDirectory::~OutputDirectory() {
  std::error_code ec;
  if (!staging_.empty()) fs::remove_all(staging_, ec);
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

void OutputDirectory::write(const std::string& name, const std::string& content) {
  if (committed_) throw IoError("output directory " + dir_.string() + " already committed");
  write_new_file(staging_ / name, content, true);
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
  buffer_.clear();
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
