// `pcsim run` and `pcsim plot` from the shell: exit codes, one-line reasons naming the file, the
// key and the expectation, no output on errors, the default output directory, and a clear
// message when gnuplot is missing. PCSIM_EXE (set by pcsim_boost_tests) is the executable.
#define BOOST_TEST_MODULE sieve_cli
#include <boost/test/unit_test.hpp>

#include "../support/cli_util.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using pcsim_test::exe;
using pcsim_test::Result;
using pcsim_test::sh;

struct TempDir : pcsim_test::TempDir {
  TempDir() : pcsim_test::TempDir("sieve_cli") {}
};

const std::string kCase = std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";

using pcsim_test::has;

}  // namespace

BOOST_AUTO_TEST_CASE(run_writes_the_two_files_to_the_default_directory_and_exits_0) {
  TempDir d;
  const Result r = sh("'" + exe() + "' run '" + kCase + "' --set solver.t_end=0.05", d.path);
  BOOST_TEST(r.status == 0, r.out);
  BOOST_TEST(fs::exists(d.path / "out" / "sieve_1995" / "summary.json"));
  BOOST_TEST(fs::exists(d.path / "out" / "sieve_1995" / "timeseries.csv"));
  BOOST_TEST(has(r.out, "verdict: contact KEPT"));
}

BOOST_AUTO_TEST_CASE(kernel_and_form_options_reach_the_summary) {
  TempDir d;
  const Result r = sh("'" + exe() + "' run '" + kCase +
                          "' --set solver.t_end=0.05 --kernel cpp --form dae --out res",
                      d.path);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  std::ifstream in(d.path / "res" / "summary.json");
  std::stringstream ss;
  ss << in.rdbuf();
  BOOST_TEST(has(ss.str(), "\"kernel\": \"cpp\""));
  BOOST_TEST(has(ss.str(), "\"form\": \"dae\""));
}

// Each --set takes exactly one KEY=VALUE, so options may come before the case file.
BOOST_AUTO_TEST_CASE(set_options_may_precede_the_case_file) {
  TempDir d;
  const Result r = sh("'" + exe() + "' run --set solver.t_end=0.02 --set output.dt=0.01 '" +
                          kCase + "' --out res",
                      d.path);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  std::ifstream in(d.path / "res" / "timeseries.csv");
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  BOOST_TEST(lines == 4);  // header + t = 0, 0.01, 0.02
}

// Each error class: non-zero exit, one line "pcsim: error: ..." naming the file, the key and
// the expectation, and nothing written.
BOOST_AUTO_TEST_CASE(case_errors_exit_nonzero_with_one_line_and_write_nothing) {
  struct Bad {
    std::string args, key, expected;
  };
  const std::vector<Bad> bad = {
      {"--set parameters.mass=3", "parameters.mass", "expected a key"},
      {"--set parameters.m1=heavy", "parameters.m1", "expected a number"},
      {"--set parameters.m2=-1", "parameters.m2", "expected a positive number"},
      {"--set parameters.J0=-1", "parameters.J0", "expected a non-negative number"},
      {"--set parameters.r=0", "parameters.r", "expected a positive number"},
      {"--set solver.rtol=0", "solver.rtol", "expected a number >= 1e-13"},
      {"--set solver.rtol=1e-30", "solver.rtol", "expected a number >= 1e-13"},
      {"--set solver.t_end=-2", "solver.t_end", "expected a number >= 1e-09"},
      {"--set solver.t_end=1e-100", "solver.t_end", "expected a number >= 1e-09"},
      {"--set parameters.omega=0", "parameters.omega", "expected a positive number"},
      {"--set parameters.g=0", "parameters.g", "expected a positive number"},
      {"--set parameters.cx=0", "parameters.cx", "expected a positive number"},
      {"--set initial.s0=100", "initial.s0", "expected a roller position on the deck"},
      {"--set parameters.r=10", "parameters.r", "expected a roller radius below the deck"},
      {"--set parameters.u0=-1", "parameters.u0", "expected u0 >= r"},
      {"--set output.summary_periods=4294967296", "output.summary_periods",
       "expected an integer >= 1 and <= 1e+06"},
      {"--set output.dt=1e-9", "output.dt", "expected at most 1e+07 time-series rows"},
      {"--set output.dt=1e-320", "output.dt", "expected at most 1e+07 time-series rows"},
      {"--kernel julia", "solver.kernel", "expected \"fortran\" or \"cpp\""},
      {"--form index3", "solver.form", "expected \"ode\" or \"dae\""},
  };
  for (const auto& b : bad) {
    TempDir d;
    const Result r = sh("'" + exe() + "' run '" + kCase + "' " + b.args + " --out res", d.path);
    BOOST_TEST_CONTEXT(b.args << " -> " << r.out) {
      BOOST_TEST(r.status != 0);
      BOOST_TEST(has(r.out, "pcsim: error: " + kCase));
      BOOST_TEST(has(r.out, "'" + b.key + "'"));
      BOOST_TEST(has(r.out, b.expected));
      BOOST_TEST(std::count(r.out.begin(), r.out.end(), '\n') == 1);
      BOOST_TEST(!fs::exists(d.path / "res"));
    }
  }
  TempDir d;
  const Result r = sh("'" + exe() + "' run no_such_case.toml", d.path);
  BOOST_TEST(r.status != 0);
  BOOST_TEST(has(r.out, "no_such_case.toml"));
}

// Issue 19: a run that fails numerically (here its step budget, 10 steps where 18 are needed,
// runs out) exits 3 and keeps what it computed, marked incomplete; an excitation so fast that
// no step budget covers it (omega = 1e200) is refused before any work (exit 2), writing nothing.
BOOST_AUTO_TEST_CASE(numerical_failure_exits_3_and_keeps_what_was_computed) {
  TempDir d;
  const Result r = sh("'" + exe() + "' run '" + kCase +
                          "' --set solver.t_end=0.05 --set solver.max_steps=10 --out res",
                      d.path);
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(has(r.out, "pcsim: error:"));
  BOOST_TEST(has(r.out, "step budget of 10 steps"), r.out);
  BOOST_TEST_REQUIRE(fs::exists(d.path / "res" / "summary.json"));
  BOOST_TEST(has(pcsim_test::read(d.path / "res" / "summary.json"), "\"complete\": false"));
  BOOST_TEST(fs::exists(d.path / "res" / "timeseries.csv"));
  const Result fast = sh("'" + exe() + "' run '" + kCase +
                             "' --set solver.t_end=0.05 --set parameters.omega=1e200 --out fast",
                         d.path);
  BOOST_TEST(fast.status == 2, fast.out);
  BOOST_TEST(has(fast.out, "solver.max_steps"), fast.out);
  BOOST_TEST(!fs::exists(d.path / "fast"));
}

BOOST_AUTO_TEST_CASE(plot_writes_four_pngs_or_says_gnuplot_is_missing) {
  TempDir d;
  BOOST_TEST_REQUIRE(sh("'" + exe() + "' run '" + kCase + "' --set solver.t_end=0.1 --out res",
                        d.path).status == 0);
  // Without gnuplot on PATH: a clear message, non-zero exit, no crash.
  const Result missing = sh("PATH=/nonexistent '" + exe() + "' plot res", d.path);
  BOOST_TEST(missing.status != 0);
  BOOST_TEST(has(missing.out, "needs gnuplot"), missing.out);
  // With gnuplot (when this machine has it): four non-empty PNG files.
  if (sh("command -v gnuplot").status == 0) {
    const Result r = sh("'" + exe() + "' plot res", d.path);
    BOOST_TEST(r.status == 0, r.out);
    for (const char* f : {"theta.png", "R_u.png", "fstar.png", "xy.png"}) {
      BOOST_TEST(fs::exists(d.path / "res" / f), f);
      if (fs::exists(d.path / "res" / f)) {
        std::ifstream png(d.path / "res" / f, std::ios::binary);
        char magic[4] = {};
        png.read(magic, 4);
        BOOST_TEST((magic[1] == 'P' && magic[2] == 'N' && magic[3] == 'G'), f);
      }
    }
  }
  const Result nodir = sh("'" + exe() + "' plot does_not_exist", d.path);
  BOOST_TEST(nodir.status != 0);
  BOOST_TEST(has(nodir.out, "does_not_exist"));
}
