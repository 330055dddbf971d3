// Shared by the tests of output directories and hostile names (test_files_cli, test_files_fuzz):
// running pcsim with an argument vector (no shell, so any bytes reach it as given), case files
// with any name, a scratch tree seeded with a user's files, and the invariants checked after
// every command.
#pragma once

#include "cli_util.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace files_test {

namespace fs = std::filesystem;
using pcsim_test::Result;

/// A finished pcsim process: its exit status (-1 if a signal ended it), the signal, its wall time
/// and its stdout and stderr together.
struct Outcome {
  int status = -1;
  int signal = 0;
  double seconds = 0;
  std::string out;
};

/// Runs pcsim with `args` in `cwd` (fork/exec: no shell, so any bytes reach it as given). With
/// alarm_seconds > 0 the child gets an alarm: a runaway ends by SIGALRM.
inline Outcome run_pcsim_timed(const std::vector<std::string>& args, const fs::path& cwd,
                               unsigned alarm_seconds) {
  Outcome o;
  const std::string exe = pcsim_test::exe();
  std::vector<std::string> all = {exe};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  int fds[2];
  if (::pipe(fds) != 0) return o;
  const std::string dir = cwd.string();
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    ::close(fds[1]);
    if (::chdir(dir.c_str()) != 0) ::_exit(125);
    if (alarm_seconds > 0) ::alarm(alarm_seconds);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  char buf[4096];
  ssize_t n;
  while ((n = ::read(fds[0], buf, sizeof buf)) > 0) o.out.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int st = 0;
  ::waitpid(pid, &st, 0);
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (WIFEXITED(st)) o.status = WEXITSTATUS(st);
  if (WIFSIGNALED(st)) o.signal = WTERMSIG(st);
  return o;
}

/// Runs pcsim with `args` in `cwd` (fork/exec: no shell); stdout and stderr together.
inline Result run_pcsim(const std::vector<std::string>& args, const fs::path& cwd) {
  Outcome o = run_pcsim_timed(args, cwd, 0);
  Result r;
  r.status = o.status;
  r.out = std::move(o.out);
  return r;
}

/// `s` as a TOML basic string (quotes, backslashes and control characters escaped).
inline std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", u);
      out += b;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// A short pendulum case named `name`.
inline std::string pendulum_case(const std::string& name, double t_end = 0.2, double dt = 0.01) {
  return "name = " + toml_string(name) + "\nmodel = \"pendulum\"\n[initial]\nx = 1\n[solver]\nt_end = " +
         std::to_string(t_end) + "\n[output]\ndt = " + std::to_string(dt) + "\n";
}

/// Every path under `root` (relative) with its content for regular files ("<dir>" for
/// directories, "<link>" for links).
inline std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> m;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(root, fs::directory_options::none, ec), end; !ec && it != end;
       it.increment(ec)) {
    const auto st = it->symlink_status(ec);
    const std::string rel = fs::relative(it->path(), root, ec).string();
    if (fs::is_symlink(st)) m[rel] = "<link>";
    else if (fs::is_directory(st)) m[rel] = "<dir>";
    else m[rel] = pcsim_test::read(it->path());
  }
  return m;
}

/// True if a file named PWNED exists anywhere under root.
inline bool pwned(const fs::path& root) {
  std::error_code ec;
  for (fs::recursive_directory_iterator it(root, fs::directory_options::none, ec), end; !ec && it != end;
       it.increment(ec))
    if (it->path().filename() == "PWNED") return true;
  return fs::exists(root / "PWNED");
}

/// A scratch tree: root/ holds only work/ (the commands' working directory), and work/ is seeded
/// with a user's files: notes.txt, data/measured.csv, and a directory results/ of the user's.
struct Scratch : pcsim_test::TempDir {
  fs::path work;
  std::map<std::string, std::string> user;  // path relative to work -> content
  explicit Scratch(const std::string& tag) : pcsim_test::TempDir(tag) {
    work = path / "work";
    fs::create_directories(work / "data");
    fs::create_directories(work / "results");
    user = {{"notes.txt", "my notes\n"}, {"data/measured.csv", "t,x\n0,1\n"},
            {"results/summary.json", "{\"mine\": true}\n"}, {"results/thesis.tex", "precious\n"}};
    for (const auto& [p, c] : user) std::ofstream(work / p, std::ios::binary) << c;
  }
  /// The user's files are all there with their content.
  bool user_files_intact() const {
    for (const auto& [p, c] : user)
      if (pcsim_test::read(work / p) != c) return false;
    return true;
  }
  /// root/ holds nothing but work/ (nothing was written outside the working directory).
  bool nothing_outside() const {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(path)) {
      (void)e;
      ++n;
    }
    return n == 1 && fs::is_directory(work);
  }
};

}  // namespace files_test
