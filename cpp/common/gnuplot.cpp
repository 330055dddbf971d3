#include "common/gnuplot.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <functional>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace pcsim {

namespace fs = std::filesystem;

std::string gnuplot_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) out += ' ';
    else if (c == '\'') out += "\u2019";  // never '' (see the header)
    else if (c == '`') out += "\u2018";
    else out += c;
  }
  return out + "'";
}

std::string gnuplot_number(double v) {
  if (!(v == v) || v > 1.7976931348623157e308 || v < -1.7976931348623157e308)
    throw std::invalid_argument("not a finite number");
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::optional<fs::path> find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    std::error_code ec;
    const fs::path p = fs::path(dir) / program;
    if (fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0) return fs::absolute(p, ec);
  }
  return std::nullopt;
}

int run_program(const fs::path& program, const std::vector<std::string>& args, const fs::path& dir,
                const std::function<void(const std::function<bool(const char*, std::size_t)>&)>& feed,
                const std::string& stderr_file) {
  // Everything the child needs is prepared before fork: between fork and exec it calls only
  // async-signal-safe functions.
  const std::string prog = program.string(), where = dir.empty() ? "." : dir.string();
  std::vector<std::vector<char>> store;
  store.emplace_back(prog.begin(), prog.end());
  for (const auto& a : args) store.emplace_back(a.begin(), a.end());
  std::vector<char*> argv;
  for (auto& a : store) {
    a.push_back('\0');
    argv.push_back(a.data());
  }
  argv.push_back(nullptr);
  const std::string name = program.filename().string();
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot start " + name + ": " + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error("cannot start " + name + ": " + std::strerror(err));
  }
  if (pid == 0) {
    if (::chdir(where.c_str()) != 0) ::_exit(126);
    if (::dup2(fds[0], 0) < 0) ::_exit(126);
    if (!stderr_file.empty()) {
      const int e = ::open(stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW, 0644);
      if (e < 0 || ::dup2(e, 2) < 0) ::_exit(126);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(fds[0]);
  // The program may stop reading (an error): a write then fails with EPIPE instead of SIGPIPE.
  struct sigaction ignore{}, old{};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGPIPE, &ignore, &old);
  bool all_written = true;
  auto write_all = [&](const char* data, std::size_t size) {
    std::size_t off = 0;
    while (off < size) {
      const ssize_t n = ::write(fds[1], data + off, size - off);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        all_written = false;
        return false;
      }
      off += static_cast<std::size_t>(n);
    }
    return true;
  };
  try {
    feed(write_all);
  } catch (...) {
    ::close(fds[1]);
    ::sigaction(SIGPIPE, &old, nullptr);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    throw;
  }
  ::close(fds[1]);
  ::sigaction(SIGPIPE, &old, nullptr);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (!WIFEXITED(status)) return -1;
  if (!all_written && WEXITSTATUS(status) == 0) return 1;
  return WEXITSTATUS(status);
}

int run_gnuplot(const fs::path& dir, const std::string& script, const std::string& stderr_file) {
  const auto program = find_on_path("gnuplot");
  if (!program) throw std::runtime_error("gnuplot is not on PATH");
  return run_program(*program, {}, dir,
                     [&](const std::function<bool(const char*, std::size_t)>& write) {
                       write(script.data(), script.size());
                     },
                     stderr_file);
}

}  // namespace pcsim
