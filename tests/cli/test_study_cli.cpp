// The study commands through the pcsim executable (PCSIM_EXE, set by CTest): bad --vary
// specifications stop the command before any run (exit 2, nothing written), and rerunning a
// sweep resumes it.
#define BOOST_TEST_MODULE study_cli
#include <boost/test/unit_test.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <sys/wait.h>

#include "../study/study_fixtures.hpp"

namespace {

struct Result {
  int status;
  std::string output;
};

/// Runs pcsim with `args` (stdout and stderr captured together).
Result run_pcsim(const std::string& args, const std::filesystem::path& dir) {
  const char* exe = std::getenv("PCSIM_EXE");
  BOOST_REQUIRE_MESSAGE(exe, "PCSIM_EXE is not set (run through ctest)");
  const auto log = dir / "output.txt";
  const std::string cmd = std::string(exe) + " " + args + " > '" + log.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, study_test::slurp(log)};
}

const std::string kCase = std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";

void expect_rejected_before_running(const std::string& vary, const std::string& needle) {
  const auto dir = study_test::scratch("cli_bad");
  const auto out = dir / "out";
  const auto r = run_pcsim("sweep " + kCase + " --vary '" + vary + "' --out '" + out.string() + "'",
                       dir);
  BOOST_TEST(r.status == 2, vary << ": exit " << r.status);
  BOOST_TEST(r.output.find(needle) != std::string::npos, r.output);
  BOOST_TEST(!std::filesystem::exists(out), vary << ": the sweep started");
}

}  // namespace

BOOST_AUTO_TEST_CASE(bad_vary_stops_the_sweep_before_any_run) {
  expect_rejected_before_running("parameters.omgea=250:300:3", "unknown key 'parameters.omgea'");
  expect_rejected_before_running("parameters.omega=250:300:0", "COUNT must be at least 1");
  expect_rejected_before_running("parameters.omega=300:250:3", "reversed range");
  expect_rejected_before_running("parameters.omega=250,fast", "value 'fast' is not a number");
}

BOOST_AUTO_TEST_CASE(rerunning_a_finished_sweep_runs_nothing) {
  const auto dir = study_test::scratch("cli_resume");
  // The case file may follow the repeatable options (one value per --vary / --set).
  const std::string args = "sweep --set solver.t_end=0.02 --vary parameters.omega=270,290 "
                           "--jobs 2 --out '" + (dir / "out").string() + "' " + kCase;
  const auto first = run_pcsim(args, dir);
  BOOST_REQUIRE_MESSAGE(first.status == 0, first.output);
  BOOST_TEST(first.output.find("2 run now") != std::string::npos, first.output);
  const std::string table = study_test::slurp(dir / "out" / "sweep.csv");
  const auto second = run_pcsim(args, dir);
  BOOST_TEST(second.status == 0);
  BOOST_TEST(second.output.find("2 from an earlier run, 0 run now") != std::string::npos,
             second.output);
  BOOST_TEST(study_test::slurp(dir / "out" / "sweep.csv") == table);
  // Not a terminal: no progress bar in the output.
  BOOST_TEST(second.output.find("ETA") == std::string::npos);
}
