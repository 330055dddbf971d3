// Shared by the switching CLI tests: run the pcsim executable (PCSIM_EXE, set by
// cmake/switching.cmake) with an environment, capture its output, read files.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace switching_cli {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out;  // stdout and stderr together
};

inline std::string exe() {
  const char* e = std::getenv("PCSIM_EXE");
  return e ? e : (std::string(PCSIM_BINARY_DIR) + "/pcsim");
}

/// Runs `env ENV... pcsim ARGS` from the source tree.
inline Result pcsim(const std::string& args, const std::string& env = "") {
  Result r;
  const std::string full = "cd '" + std::string(PCSIM_SOURCE_DIR) + "' && " +
                           (env.empty() ? "" : "env " + env + " ") + "'" + exe() + "' " + args + " 2>&1";
  FILE* p = popen(full.c_str(), "r");
  char buf[4096];
  std::size_t n;
  while (p && (n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = p ? pclose(p) : -1;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

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
};

}  // namespace switching_cli
