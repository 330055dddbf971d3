// Shared by the tests that drive the pcsim executable from the shell: the executable
// (PCSIM_EXE, set by CTest), running a command line with its output and exit status, reading
// a written file whole, and a scratch directory removed at the end.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "build_tree.hpp"

namespace pcsim_test {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out;  // stdout and stderr together
};

/// The pcsim executable: PCSIM_EXE, or the build tree's.
inline std::string exe() {
  const char* e = std::getenv("PCSIM_EXE");
  return e ? e : (binary_dir() / "pcsim").string();
}

/// Runs a shell command line in `cwd`, capturing its output and exit status (-1 if it did not
/// exit normally).
inline Result sh(const std::string& cmd, const fs::path& cwd = fs::current_path()) {
  Result r;
  const std::string full = "cd '" + cwd.string() + "' && " + cmd + " 2>&1";
  FILE* p = popen(full.c_str(), "r");
  char buf[4096];
  std::size_t n;
  while (p && (n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = p ? pclose(p) : -1;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// The file's bytes ("" if it cannot be read).
inline std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

inline bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// A fresh directory under the system's temporary directory, removed with everything in it.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    static int n = 0;
    path = fs::temp_directory_path() /
           ("pcsim_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

/// A fresh scratch directory in the build tree: test-scratch/<suite>/<name>, emptied first
/// (kept after the test, for a look at what a failing run wrote).
inline fs::path scratch(const std::string& suite, const std::string& name) {
  const fs::path d = binary_dir() / "test-scratch" / suite / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Runs `pcsim ARGS` (PCSIM_EXE) in `dir`, its output (stdout and stderr) logged to
/// dir/output.txt and returned with the exit status. ARGS is a command line: quote paths.
inline Result run_pcsim(const std::string& args, const fs::path& dir) {
  const auto log = dir / "output.txt";
  const int rc = std::system((exe() + " " + args + " > '" + log.string() + "' 2>&1").c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, read(log)};
}

}  // namespace pcsim_test
