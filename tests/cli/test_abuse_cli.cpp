// pcsim under abuse, from the shell (issue 15): output written whole or not at all with the
// system's reason, one writer per output directory, derived cases with their own names, and
// inputs that are not case files. PCSIM_EXE (set by pcsim_boost_tests) is the executable.
#define BOOST_TEST_MODULE sim_abuse_cli
#include <boost/test/unit_test.hpp>

#include "../support/cli_util.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using pcsim_test::exe;
using pcsim_test::Result;
using pcsim_test::sh;

struct TempDir : pcsim_test::TempDir {
  TempDir() : pcsim_test::TempDir("abuse") {}
};

const std::string kCase = std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";
using pcsim_test::has;

}  // namespace

// A full disk, imitated by a file-size limit (RLIMIT_FSIZE; SIGXFSZ ignored so write() fails
// with EFBIG): the run fails naming the file and the system's reason, not "Success", and the
// output directory holds neither file.
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(full_disk_leaves_neither_file_and_says_why, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  TempDir d;
  const Result r = sh("trap '' XFSZ; ulimit -f 200; '" + exe() + "' run '" + kCase +
                          "' --set solver.t_end=1 --out res",
                      d.path);
  BOOST_TEST(r.status != 0, r.out);
  BOOST_TEST(has(r.out, "File too large"), r.out);
  BOOST_TEST(!has(r.out, "Success"), r.out);
  BOOST_TEST(!fs::exists(d.path / "res" / "summary.json"));
  BOOST_TEST(!fs::exists(d.path / "res" / "timeseries.csv"));
}

// Two runs into one --out at once: the second is refused at once with a clear message (the
// first holds the directory's lock), and the first completes with its own pair of files.
BOOST_AUTO_TEST_CASE(second_run_into_the_same_directory_is_refused) {
  TempDir d;
  // A run long enough (seconds) for the second to start while it holds the directory.
  std::ofstream(d.path / "long.toml") << "model = \"pendulum\"\n[initial]\nx = 1\n[solver]\nt_end = 3000\n"
                                         "[output]\ndt = 0.01\n";
  const std::string run = "'" + exe() + "' run long.toml --out res";
  // The first run is ended after 20 s at most (timeout): the test needs it only to hold the lock
  // while the second one tries (a sanitizer build runs it 100 times slower than a release build).
  FILE* first = popen(("cd '" + d.path.string() + "' && timeout 20 " + run + " > first.log 2>&1").c_str(), "r");
  // Wait until the first run holds the lock (its staging directory appears).
  bool started = false;
  for (int i = 0; i < 400 && !started; ++i) {
    for (const auto& e : fs::directory_iterator(d.path))
      started = started || e.path().filename().string().find(".res.staging") == 0;
    if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  BOOST_REQUIRE(started);
  const Result second = sh(run, d.path);
  BOOST_TEST(second.status == 2, second.out);
  BOOST_TEST(has(second.out, "in use by another pcsim run"), second.out);
  const int st = pclose(first);
  // The first run completed with its own files, or was ended by the timeout (exit 124): then
  // it left no output at all, or, when the timeout struck after the directory was committed
  // (a sanitizer build on a loaded machine takes about 20 s here), the complete pair; never a
  // mix.
  const int code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  BOOST_TEST((code == 0 || code == 124), code);
  if (code == 0) BOOST_TEST(fs::exists(d.path / "res" / "summary.json"));
  if (fs::exists(d.path / "res")) {
    BOOST_TEST(fs::exists(d.path / "res" / "summary.json"));
    BOOST_TEST(fs::exists(d.path / "res" / "timeseries.csv"));
  }
}

BOOST_AUTO_TEST_CASE(a_directory_is_not_a_case_file) {
  TempDir d;
  const Result r = sh("'" + exe() + "' run '" + d.path.string() + "'", d.path);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(has(r.out, "is a directory, not a case file"), r.out);
}

// best.toml is a case of its own: running it writes out/<case>-optimized, not over the original
// case's out/<case>.
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(optimized_case_has_its_own_name, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  TempDir d;
  const Result r = sh("'" + exe() + "' optimize '" + kCase +
                          "' --set solver.t_end=0.05 --vary parameters.e=0.009:0.011 --max-evals 2 "
                          "--no-default-constraints --out opt",
                      d.path);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  std::ifstream best(d.path / "opt" / "best.toml");
  std::string text((std::istreambuf_iterator<char>(best)), std::istreambuf_iterator<char>());
  const bool named = has(text, "name = 'sieve_1995-optimized'") || has(text, "name = \"sieve_1995-optimized\"");
  BOOST_TEST(named, text);
}
