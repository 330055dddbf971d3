// A generator of hostile `pcsim steady` and `pcsim response` requests (issue 19, Evidence: the
// fuzzers extended to the steady and response commands). From a small forced Duffing case (an
// inline model whose orbit period is 2 pi / omega), each input mutates the case file (omega,
// the period expression, output.dt, the step budget, tolerances, a deleted line) and the
// command line: --set of hostile numbers (nan, inf, 1e-9, 1e400, 1e-400, negative, text) on
// parameters, initial.* and solver keys, unknown keys; for steady --periods, --method,
// --max-iterations, --transient-periods; for response --vary KEY=START:STOP:COUNT with NaN, inf,
// reversed ranges, zero, negative, fractional and huge counts, lists, unknown and initial.* keys.
// After every input the invariants hold:
//   - pcsim exits 0, 2 or 3 (no crash, no abort, no exit 1);
//   - it ends within the time bound (a runaway is killed by SIGALRM and fails the test); the
//     slowest input is reported;
//   - nothing was created outside the scratch working directory, the user's files there are
//     unchanged, and no staging or lock file is left beside the output directory;
//   - a refused request (exit 2) wrote nothing: no output directory;
//   - a finished one (exit 0) wrote a marked output directory with its result file.
// CTest runs a fixed seed (fewer inputs under the sanitizers of a Debug build); longer runs by
// hand: PCSIM_FUZZ_STEADY=<inputs> PCSIM_FUZZ_SEED=<n> PCSIM_EXE=build/pcsim build/test_steady_fuzz
#define BOOST_TEST_MODULE sim_steady_fuzz
#include <boost/test/unit_test.hpp>

#include "../support/files_util.hpp"
#include "../support/build_tree.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// 500 inputs take about 10 s; under ASan/UBSan each run is several times slower: 60.
const int kDefaultInputs = pcsim_test::slow_build() ? 60 : 500;
constexpr unsigned kTimeLimitSeconds = 60;  // per input; the slowest is reported

const char* const kBaseCase =
    "name = \"duffing\"\n"
    "[model]\n"
    "name = \"duffing\"\n"
    "coordinates = [\"x\"]\n"
    "period = \"PERIOD\"\n"
    "[model.parameters]\n"
    "c = { value = 0.1, min = 0.0 }\n"
    "k = { value = 1.0 }\n"
    "k3 = { value = 1.0 }\n"
    "F = { value = 0.5 }\n"
    "omega = { value = OMEGA, positive = true }\n"
    "[model.energy]\n"
    "kinetic = \"0.5*x_d^2\"\n"
    "potential = \"0.5*k*x^2 + 0.25*k3*x^4\"\n"
    "dissipation = \"0.5*c*x_d^2\"\n"
    "[model.forces]\n"
    "x = \"F*cos(omega*t)\"\n"
    "[initial]\n"
    "x = 0.1\n"
    "[solver]\n"
    "rtol = 1e-7\n"
    "atol = 1e-9\n"
    "MAXSTEPS"
    "[output]\n"
    "dt = DT\n";

const std::vector<std::string> kNumbers = {
    "nan", "inf", "-inf", "0", "-1", "1e-9", "1e-300", "1e-400", "1e400", "1e300", "1e9", "1e-3",
    "0.5", "1", "1.2", "2", "3", "abc", "", "1,2", "0x10", "+1", "1e", "--1"};
const std::vector<std::string> kSafeNumbers = {"0.8", "1", "1.2", "0.5", "2"};
const std::vector<std::string> kSetKeys = {
    "parameters.omega", "parameters.F", "parameters.c", "parameters.k3", "initial.x", "initial.x_d",
    "solver.rtol", "solver.atol", "solver.max_steps", "solver.t_end", "output.dt", "parameters.omgea",
    "initial.y", "steady.periods", "solver.method", "model.period"};
const std::vector<std::string> kSafeSetKeys = {"parameters.omega", "parameters.F", "parameters.c", "initial.x"};
const std::vector<std::string> kVaryKeys = {
    "parameters.omega", "parameters.omega", "parameters.F", "parameters.c", "initial.x",
    "initial.x_d", "solver.rtol", "parameters.nope", "", "output.dt", "solver.max_steps",
    "parameters.omega.value", "name"};
// Counts above the grid's limit of 1e7 points are refused before work. A count below it is a
// legitimate request whose time grows with the count (one orbit per point, a few ms each here),
// so the generator's valid counts stay small enough for the per-input time bound.
const std::vector<std::string> kCounts = {"0", "1", "2", "3", "-1", "2.5", "nan", "inf", "1e9", "30",
                                           "10000001", "18446744073709551617", "", "x"};

template <class T>
const T& pick(std::mt19937& rng, const std::vector<T>& v) {
  return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
}
bool chance(std::mt19937& rng, int percent) { return std::uniform_int_distribution<int>(0, 99)(rng) < percent; }

void replace(std::string& s, const std::string& what, const std::string& with) {
  s.replace(s.find(what), what.size(), with);
}

std::string mutated_case(std::mt19937& rng, int h) {
  std::string c = kBaseCase;
  replace(c, "OMEGA", chance(rng, h) ? pick(rng, kNumbers) : pick(rng, kSafeNumbers));
  const std::vector<std::string> periods = {"2*pi/omega", "2*pi/omega", "2*pi/omega", "1e10", "0", "-1",
                                            "nan", "inf", "1e-12", "2*pi/(omega-omega)", "omega^1000",
                                            "2*pi/omega*1e9", "", "x", "t"};
  replace(c, "PERIOD", chance(rng, h) ? pick(rng, periods) : "2*pi/omega");
  replace(c, "MAXSTEPS", chance(rng, h) ? "max_steps = " + pick(rng, std::vector<std::string>{"1", "10", "1000", "1000000000", "0", "-1", "1e3"}) + "\n" : "");
  replace(c, "DT", chance(rng, h) ? pick(rng, std::vector<std::string>{"1e-9", "1e-300", "10", "0", "-0.1", "nan", "1e300"}) : "0.05");
  if (chance(rng, h / 2)) {  // delete one line
    std::vector<std::size_t> starts = {0};
    for (std::size_t i = 0; i + 1 < c.size(); ++i)
      if (c[i] == '\n') starts.push_back(i + 1);
    const std::size_t a = pick(rng, starts);
    c.erase(a, c.find('\n', a) - a + 1);
  }
  return c;
}

using files_test::Outcome;

// fork/exec (no shell) in cwd with an alarm: a runaway ends by SIGALRM.
Outcome run(const std::vector<std::string>& args, const fs::path& cwd) {
  return files_test::run_pcsim_timed(args, cwd, kTimeLimitSeconds);
}

std::string shown(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += " '" + a + "'";
  return s;
}

}  // namespace

BOOST_AUTO_TEST_CASE(hostile_steady_and_response_requests_keep_the_invariants) {
  const char* n_env = std::getenv("PCSIM_FUZZ_STEADY");
  const char* seed_env = std::getenv("PCSIM_FUZZ_SEED");
  const int inputs = n_env ? std::atoi(n_env) : kDefaultInputs;
  const unsigned seed = seed_env ? static_cast<unsigned>(std::atoi(seed_env)) : 19u;
  std::mt19937 rng(seed);
  files_test::Scratch s("steady_fuzz");
  int counts[4] = {0, 0, 0, 0};  // exit 0, 2, 3, other
  int steady_runs = 0, response_runs = 0;
  double slowest = 0;
  std::string slowest_input;
  for (int i = 0; i < inputs; ++i) {
    // How hostile this input is: the chance of each mutation (a third of the inputs are mostly
    // valid, so the generator reaches the shooting and the response loop, not only refusals).
    const int h = pick(rng, std::vector<int>{3, 10, 30});
    const std::string text = mutated_case(rng, h);
    std::ofstream(s.work / "c.toml", std::ios::binary | std::ios::trunc) << text;
    const bool steady = chance(rng, 50);
    std::vector<std::string> args = {steady ? "steady" : "response", "c.toml", "--out", "o"};
    for (int k = std::uniform_int_distribution<int>(0, 2)(rng); k > 0; --k)
      args.push_back("--set=" + (chance(rng, 3 * h) ? pick(rng, kSetKeys) : pick(rng, kSafeSetKeys)) + "=" + (chance(rng, 2 * h) ? pick(rng, kNumbers) : pick(rng, kSafeNumbers)));
    if (steady) {
      ++steady_runs;
      if (chance(rng, h)) args.push_back("--periods=" + pick(rng, std::vector<std::string>{"0", "1", "2", "-1", "1e9", "1000000", "nan", "x"}));
      if (chance(rng, h)) args.push_back("--method=" + pick(rng, std::vector<std::string>{"auto", "explicit", "radau", "bogus", ""}));
      if (chance(rng, h)) args.push_back("--max-iterations=" + pick(rng, std::vector<std::string>{"0", "1", "3", "1000000", "-1"}));
      if (chance(rng, h)) args.push_back("--transient-periods=" + pick(rng, std::vector<std::string>{"0", "1", "1e6", "1000000000", "-5", "nan"}));
    } else {
      ++response_runs;
      std::string spec;
      const int shape = std::uniform_int_distribution<int>(0, 3)(rng);
      const std::vector<std::string> safe_counts = {"1", "2", "3", "5"};
      const auto value = [&] { return chance(rng, h) ? pick(rng, kNumbers) : pick(rng, kSafeNumbers); };
      if (shape == 0) spec = value() + ":" + value() + ":" + (chance(rng, 2 * h) ? pick(rng, kCounts) : pick(rng, safe_counts));
      else if (shape == 1) spec = pick(rng, kSafeNumbers) + ":" + pick(rng, kSafeNumbers) + ":" + (chance(rng, 2 * h) ? pick(rng, kCounts) : pick(rng, safe_counts));
      else if (shape == 2) spec = value() + "," + value() + (chance(rng, 50) ? "," + value() : "");
      else spec = value() + ":" + value();
      args.push_back("--vary=" + (chance(rng, 2 * h) ? pick(rng, kVaryKeys) : std::string("parameters.omega")) + "=" + spec);
      if (chance(rng, h)) args.push_back("--vary=" + pick(rng, kVaryKeys) + "=" + value());  // a second --vary
      if (chance(rng, h)) args.push_back("--periods=" + pick(rng, std::vector<std::string>{"0", "1", "2", "1e9", "nan"}));
      args.push_back("--jobs=1");
    }
    const Outcome r = run(args, s.work);
    const std::string what = shown(args) + "\n" + text + "\n--- output:\n" + r.out.substr(0, 2000);
    if (r.seconds > slowest) {
      slowest = r.seconds;
      slowest_input = shown(args);
    }
    BOOST_TEST(r.signal == 0, "signal " << r.signal << (r.signal == SIGALRM ? " (time bound)" : "") << ":" << what);
    BOOST_TEST((r.status == 0 || r.status == 2 || r.status == 3), "exit " << r.status << ":" << what);
    counts[r.status == 0 ? 0 : r.status == 2 ? 1 : r.status == 3 ? 2 : 3]++;
    if (r.status == 2) BOOST_TEST(!fs::exists(s.work / "o"), "a refused request wrote o/:" << what);
    if (r.status == 0) {
      BOOST_TEST(fs::exists(s.work / "o" / ".pcsim-output"), what);
      BOOST_TEST(fs::exists(s.work / "o" / (steady ? "steady.json" : "response.csv")), what);
    }
    BOOST_TEST(s.nothing_outside(), what);
    BOOST_TEST(s.user_files_intact(), what);
    // Nothing but the user's files, the case and the output directory in work/: no staging
    // directory or lock file left behind.
    for (const auto& e : fs::directory_iterator(s.work)) {
      const std::string name = e.path().filename().string();
      BOOST_TEST((name == "c.toml" || name == "o" || name == "notes.txt" || name == "data" || name == "results"),
                 "left behind: " << name << ":" << what);
    }
    std::error_code ec;
    fs::remove_all(s.work / "o", ec);
  }
  BOOST_TEST_MESSAGE("steady/response fuzz, seed " << seed << ": " << inputs << " inputs (" << steady_runs
                     << " steady, " << response_runs << " response): exit 0: " << counts[0] << ", exit 2: "
                     << counts[1] << ", exit 3: " << counts[2] << ", other: " << counts[3] << "; slowest "
                     << slowest << " s:" << slowest_input);
  BOOST_TEST(counts[0] > 0);  // the generator reaches the computation, not only the refusals
  BOOST_TEST(counts[1] > 0);
}
