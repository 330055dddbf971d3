// Issue 19, "a case file must never run a command" and "never lose or mix a user's files", from
// the outside: hostile case and directory names through run, plot and the incline study; case
// names that are paths; output directories owned by the command that made them; a run killed
// with SIGKILL; pcsim plot of files that are not a run's (a link to /dev/zero, a FIFO, a huge
// file) or of a half-written run. PCSIM_EXE (set by pcsim_boost_tests) is the executable.
#define BOOST_TEST_MODULE sim_files_cli
#include <boost/test/unit_test.hpp>

#include "../support/files_util.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using files_test::run_pcsim;
using files_test::Scratch;
using pcsim_test::has;
using pcsim_test::Result;

namespace {

const std::string kSieve = std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";

bool gnuplot_available() { return pcsim_test::sh("command -v gnuplot >/dev/null").status == 0; }

std::vector<fs::path> pngs(const fs::path& dir) {
  std::vector<fs::path> v;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png" || e.path().filename().string().find(".part") != std::string::npos)
      v.push_back(e.path());
  return v;
}

// The names of the issue and their variants: quotes of both kinds, gnuplot's system() and
// backquotes, line breaks, backslashes, a run of single quotes (gnuplot 5.4 ends a string at
// four), shell metacharacters, unicode.
const std::vector<std::string> kHostile = {
    "x\"; system(\"touch PWNED\"); #",
    "x'; system('touch PWNED'); #",
    "x''''; system(\"touch PWNED\"); print ''''",
    "q'`touch PWNED`'",
    "`touch PWNED`",
    "x\\'; system('touch PWNED'); #",
    "x'.system('touch PWNED').'",
    "$(touch PWNED)",
    "a;touch PWNED;b",
    "@sys",
    "Müller's “sieve” ∑",
};

}  // namespace

// A case named like the issue's example runs (or is refused), and pcsim plot of its directory
// draws the figures: nothing is executed, no PWNED appears, the user's files survive.
BOOST_AUTO_TEST_CASE(hostile_case_names_run_and_plot_without_running_anything) {
  Scratch s("files_names");
  const bool plot = gnuplot_available();
  for (const auto& name : kHostile) {
    std::ofstream(s.work / "c.toml") << files_test::pendulum_case(name);
    const Result r = run_pcsim({"run", "c.toml"}, s.work);
    if (name.find('\\') != std::string::npos) {  // a separator on some systems: refused
      BOOST_TEST(r.status == 2, name << ": " << r.out);
      BOOST_TEST(has(r.out, "key 'name'"), r.out);
      continue;
    }
    BOOST_TEST(r.status == 0, name << ": " << r.out);
    const fs::path out = s.work / "out" / name;
    BOOST_TEST(fs::exists(out / "summary.json"), name);
    if (plot) {
      const Result p = run_pcsim({"plot", (fs::path("out") / name).string()}, s.work);
      BOOST_TEST(p.status == 0, name << ": " << p.out);
      BOOST_TEST(fs::exists(out / "coordinates.png"), name);
    }
    BOOST_TEST(!files_test::pwned(s.path), name);
  }
  BOOST_TEST(s.user_files_intact());
  BOOST_TEST(s.nothing_outside());
}

// The same names as directories given to pcsim plot (and to --out, a path the user chose).
BOOST_AUTO_TEST_CASE(hostile_directory_names_given_to_plot) {
  if (!gnuplot_available()) return;
  Scratch s("files_dirs");
  std::ofstream(s.work / "c.toml") << files_test::pendulum_case("plain");
  std::vector<std::string> names = kHostile;
  names.push_back("line\nbreak'; system('touch PWNED')");
  names.push_back("tab\there");
  for (const auto& name : names) {
    const Result r = run_pcsim({"run", "c.toml", "--out", name}, s.work);
    BOOST_TEST_REQUIRE(r.status == 0, name << ": " << r.out);
    const Result p = run_pcsim({"plot", name}, s.work);
    BOOST_TEST(p.status == 0, name << ": " << p.out);
    BOOST_TEST(fs::exists(s.work / name / "coordinates.png"), name);
    BOOST_TEST(!files_test::pwned(s.path), name);
  }
  BOOST_TEST(s.user_files_intact());
}

// pcsim study incline used std::system and pasted the case name into its gnuplot script.
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(incline_study_with_a_hostile_case_name_runs_nothing, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  Scratch s("files_incline");
  for (const std::string name : {"x\"; system(\"touch PWNED\"); #", "x''''; system('touch PWNED'); print ''''"}) {
    std::ofstream(s.work / "c.toml") << "name = " << files_test::toml_string(name)
                                     << "\nmodel = \"sieve\"\n[solver]\nt_end = 0.05\n";
    const Result r = run_pcsim({"study", "incline", "c.toml", "--vary", "parameters.omega=260", "-j", "1"}, s.work);
    BOOST_TEST(r.status == 0, r.out);
    BOOST_TEST(fs::exists(s.work / "out" / (name + "-incline") / "incline.csv"));
    if (gnuplot_available()) BOOST_TEST(fs::exists(s.work / "out" / (name + "-incline") / "incline.png"), r.out);
    BOOST_TEST(!files_test::pwned(s.path));
  }
  BOOST_TEST(s.user_files_intact());
}

// A name is a file name, not a path: every command refuses the issue's "" and
// "../../escaped" and their variants with exit 2, naming the file and the key, and writes
// nothing (no out/ at all, nothing outside).
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(case_names_that_are_not_file_names_are_refused_by_every_command, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  Scratch s("files_badnames");
  const std::vector<std::string> bad = {"", ".", "..", "../../escaped", "a/b", "/abs", "a\\b", "..\\x",
                                        "x\ny", "tab\t", std::string("nul\0x", 5), "\x7f", ".hidden",
                                        std::string(129, 'a'), "bad\xff utf8"};
  const std::vector<std::vector<std::string>> commands = {
      {"run", "c.toml"},
      {"steady", "c.toml"},
      {"response", "c.toml", "--vary", "parameters.omega=260,270"},
      {"sweep", "c.toml", "--vary", "parameters.omega=260,270"},
      {"optimize", "c.toml", "--vary", "parameters.e=0.009:0.011", "--max-evals", "1"},
      {"study", "incline", "c.toml", "--vary", "parameters.omega=260", "--no-plot"}};
  for (const auto& name : bad) {
    std::ofstream(s.work / "c.toml", std::ios::binary)
        << "name = " << files_test::toml_string(name) << "\nmodel = \"sieve\"\n[solver]\nt_end = 0.05\n";
    for (const auto& cmd : commands) {
      const Result r = run_pcsim(cmd, s.work);
      BOOST_TEST(r.status == 2, cmd[0] << " '" << name << "': " << r.out);
      // TOML itself refuses invalid UTF-8 and NUL; every other name reaches the name check.
      if (name.find('\0') == std::string::npos && name.find('\xff') == std::string::npos)
        BOOST_TEST(has(r.out, "c.toml: key 'name': expected a case name"), cmd[0] << ": " << r.out);
    }
    BOOST_TEST(!fs::exists(s.work / "out"), name);
    BOOST_TEST(s.nothing_outside(), name);
  }
  // Without a name key the file's name is the case name: the same rule, and the message says so.
  std::ofstream(s.work / ".hidden.toml") << "model = \"sieve\"\n";
  const Result r = run_pcsim({"run", ".hidden.toml"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "set one"), r.out);
  // A name of exactly 128 bytes is fine.
  std::ofstream(s.work / "c.toml") << files_test::pendulum_case(std::string(128, 'b'));
  BOOST_TEST(run_pcsim({"run", "c.toml"}, s.work).status == 0);
  BOOST_TEST(s.user_files_intact());
}

// Each command owns the directories it makes (.pcsim-output names it) and refuses another's:
// a sweep or optimize never writes into a run's directory, a run never replaces a sweep's (its
// journal survives), and no command writes into or replaces a user's directory, the current
// directory or a parent.
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(commands_own_their_directories_and_refuse_each_others, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  Scratch s("files_owner");
  std::ofstream(s.work / "c.toml") << "name = \"c\"\nmodel = \"sieve\"\n[solver]\nt_end = 0.05\n";
  BOOST_TEST_REQUIRE(run_pcsim({"run", "c.toml", "--out", "r"}, s.work).status == 0);
  BOOST_TEST(pcsim_test::read(s.work / "r" / ".pcsim-output").rfind("run\n", 0) == 0);
  BOOST_TEST_REQUIRE(run_pcsim({"sweep", "c.toml", "--vary", "parameters.omega=260,270", "-j", "1", "--out", "sw"}, s.work).status == 0);
  BOOST_TEST(pcsim_test::read(s.work / "sw" / ".pcsim-output").rfind("sweep\n", 0) == 0);
  const auto run_files = files_test::snapshot(s.work / "r");
  const auto sweep_files = files_test::snapshot(s.work / "sw");

  Result r = run_pcsim({"sweep", "c.toml", "--vary", "parameters.omega=260", "--out", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "belongs to `pcsim run`"), r.out);
  r = run_pcsim({"optimize", "c.toml", "--vary", "parameters.e=0.009:0.011", "--max-evals", "1", "--out", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  r = run_pcsim({"response", "c.toml", "--vary", "parameters.omega=260", "--out", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(files_test::snapshot(s.work / "r") == run_files);
  for (const char* cmd : {"run", "steady"}) {
    r = run_pcsim({cmd, "c.toml", "--out", "sw"}, s.work);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(has(r.out, "belongs to `pcsim sweep`"), r.out);
  }
  BOOST_TEST(files_test::snapshot(s.work / "sw") == sweep_files);  // the journal survives

  // A directory of the previous version (no marker): accepted when it holds only the command's
  // own files, refused when it holds another command's journal.
  fs::create_directories(s.work / "old_run");
  fs::copy_file(s.work / "r" / "summary.json", s.work / "old_run" / "summary.json");
  fs::copy_file(s.work / "r" / "timeseries.csv", s.work / "old_run" / "timeseries.csv");
  BOOST_TEST(run_pcsim({"run", "c.toml", "--out", "old_run"}, s.work).status == 0);
  BOOST_TEST(fs::exists(s.work / "old_run" / ".pcsim-output"));
  fs::create_directories(s.work / "old_sweep");
  fs::copy_file(s.work / "sw" / "sweep.csv", s.work / "old_sweep" / "sweep.csv");
  fs::copy_file(s.work / "sw" / "sweep.key", s.work / "old_sweep" / "sweep.key");
  r = run_pcsim({"run", "c.toml", "--out", "old_sweep"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "sweep.csv"), r.out);
  BOOST_TEST(fs::exists(s.work / "old_sweep" / "sweep.csv"));
  BOOST_TEST(run_pcsim({"sweep", "c.toml", "--vary", "parameters.omega=260,270", "-j", "1", "--out", "old_sweep"}, s.work).status == 0);

  // A user's directories, the working directory and its parents.
  for (const char* out : {"results", "data", ".", "..", "./", "../work", "r/..", "/"}) {
    for (const std::vector<std::string>& cmd :
         std::vector<std::vector<std::string>>{{"run", "c.toml", "--out", out},
                                              {"sweep", "c.toml", "--vary", "parameters.omega=260", "--out", out},
                                              {"optimize", "c.toml", "--vary", "parameters.e=0.009:0.011", "--max-evals", "1", "--out", out}}) {
      r = run_pcsim(cmd, s.work);
      BOOST_TEST(r.status == 2, cmd[0] << " --out " << out << ": " << r.out);
    }
  }
  // A link where optimize writes its history would make it write through the link: refused.
  BOOST_TEST_REQUIRE(run_pcsim({"optimize", "c.toml", "--vary", "parameters.e=0.009:0.011", "--max-evals", "1",
                                "--no-default-constraints", "--out", "opt"}, s.work).status == 0);
  fs::remove(s.work / "opt" / "optimize.csv");
  fs::create_symlink(s.work / "notes.txt", s.work / "opt" / "optimize.csv");
  r = run_pcsim({"optimize", "c.toml", "--vary", "parameters.e=0.009:0.011", "--max-evals", "1",
                 "--no-default-constraints", "--out", "opt"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "not a regular file"), r.out);
  // A file of the user's in a run directory is never deleted by the next run: refused instead.
  std::ofstream(s.work / "r" / "my-notes.txt") << "mine";
  r = run_pcsim({"run", "c.toml", "--out", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "my-notes.txt"), r.out);
  BOOST_TEST(pcsim_test::read(s.work / "r" / "my-notes.txt") == "mine");
  BOOST_TEST(s.user_files_intact());
  BOOST_TEST(s.nothing_outside());
  BOOST_TEST(!fs::exists(s.path / "out"));
  // No lock file is left beside any directory.
  for (const auto& e : fs::directory_iterator(s.work))
    BOOST_TEST(e.path().extension() != ".lock", e.path());
}

// A run killed with SIGKILL leaves its staging directory; the next run of the same directory
// removes it (its process is gone and it carries pcsim's marker), leaves no lock file, and
// writes complete output. A staging-like directory that pcsim did not make is left alone.
BOOST_AUTO_TEST_CASE(staging_of_a_killed_run_is_removed_by_the_next_run) {
  Scratch s("files_kill");
  std::ofstream(s.work / "long.toml") << files_test::pendulum_case("long", 5e4, 0.01);
  std::ofstream(s.work / "short.toml") << files_test::pendulum_case("long", 0.2);
  fs::create_directories(s.work / "out" / ".long.staging-999999999-0");  // not pcsim's: no marker
  const std::string exe = pcsim_test::exe();
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(s.work.c_str()) != 0) ::_exit(125);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(exe.c_str(), exe.c_str(), "run", "long.toml", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const std::string prefix = ".long.staging-" + std::to_string(pid) + "-";
  fs::path staging;
  for (int i = 0; i < 2000 && staging.empty(); ++i) {
    for (const auto& e : fs::directory_iterator(s.work / "out"))
      if (e.path().filename().string().rfind(prefix, 0) == 0 && fs::exists(e.path() / "timeseries.csv"))
        staging = e.path();
    if (staging.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  BOOST_TEST_REQUIRE(!staging.empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // mid-run, some rows written
  ::kill(pid, SIGKILL);
  int st = 0;
  ::waitpid(pid, &st, 0);
  BOOST_TEST(WIFSIGNALED(st));
  BOOST_TEST(fs::exists(staging));  // what the killed run left
  BOOST_TEST(fs::exists(s.work / "out" / ".long.lock"));
  const Result r = run_pcsim({"run", "short.toml"}, s.work);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  BOOST_TEST(!fs::exists(staging));
  BOOST_TEST(!fs::exists(s.work / "out" / ".long.lock"));
  BOOST_TEST(fs::exists(s.work / "out" / ".long.staging-999999999-0"));
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(s.work / "out")) left.push_back(e.path().filename().string());
  BOOST_TEST(left.size() == 2u);  // long/ and the directory that is not pcsim's
  BOOST_TEST(fs::exists(s.work / "out" / "long" / "summary.json"));
  const std::string csv = pcsim_test::read(s.work / "out" / "long" / "timeseries.csv");
  BOOST_TEST(std::count(csv.begin(), csv.end(), '\n') == 22);  // header + t = 0, 0.01, ..., 0.2
  BOOST_TEST(s.user_files_intact());
}

// pcsim plot reads only regular files of bounded size: a time series that links to /dev/zero,
// a FIFO, or a 2 GiB file is refused at once (exit 2) with the reason, before anything is read.
BOOST_AUTO_TEST_CASE(plot_refuses_devices_fifos_and_huge_files) {
  Scratch s("files_plotsize");
  std::ofstream(s.work / "c.toml") << files_test::pendulum_case("c");
  BOOST_TEST_REQUIRE(run_pcsim({"run", "c.toml", "--out", "r"}, s.work).status == 0);
  const fs::path csv = s.work / "r" / "timeseries.csv";
  fs::remove(csv);
  fs::create_symlink("/dev/zero", csv);
  Result r = run_pcsim({"plot", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "not a regular file"), r.out);
  fs::remove(csv);
  BOOST_TEST_REQUIRE(::mkfifo(csv.c_str(), 0644) == 0);
  r = run_pcsim({"plot", "r"}, s.work);  // must not wait for a writer
  BOOST_TEST(r.status == 2, r.out);
  fs::remove(csv);
  {
    std::ofstream(csv) << "t,x\n";
  }
  fs::resize_file(csv, (std::uintmax_t{2} << 30));  // sparse: no disk used
  r = run_pcsim({"plot", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "MiB"), r.out);
  fs::remove(csv);
  fs::remove(s.work / "r" / "summary.json");
  fs::create_symlink("/dev/zero", s.work / "r" / "summary.json");
  std::ofstream(csv) << "t,x\n0,1\n";
  r = run_pcsim({"plot", "r"}, s.work);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pngs(s.work / "r").empty());
}

// pcsim plot of a half-written run (a cut-off time series, a header alone, a short row, a
// summary cut off or without its window) exits 2 naming the file, and leaves no figure.
BOOST_AUTO_TEST_CASE(plot_of_a_half_written_run_exits_2_and_leaves_no_figure) {
  Scratch s("files_plothalf");
  std::ofstream(s.work / "c.toml") << files_test::pendulum_case("c");
  BOOST_TEST_REQUIRE(run_pcsim({"run", "c.toml", "--out", "r"}, s.work).status == 0);
  const std::string csv = pcsim_test::read(s.work / "r" / "timeseries.csv");
  const std::string sum = pcsim_test::read(s.work / "r" / "summary.json");
  const std::string header = csv.substr(0, csv.find('\n') + 1);
  struct Half {
    std::string csv, sum, expect;
  };
  const std::vector<Half> cases = {
      {csv.substr(0, csv.size() / 2), sum, "cut off"},
      {header, sum, "no rows"},
      {"", sum, "empty"},
      {header + "0,1\n", sum, "fields"},
      {csv, sum.substr(0, sum.size() / 2), "summary.json"},
      {csv, "{\"case\": \"c\"}", "not a complete pcsim summary"},
      {csv, "[1, 2]", "summary"},
  };
  for (const auto& h : cases) {
    std::ofstream(s.work / "r" / "timeseries.csv", std::ios::binary | std::ios::trunc) << h.csv;
    std::ofstream(s.work / "r" / "summary.json", std::ios::binary | std::ios::trunc) << h.sum;
    const Result r = run_pcsim({"plot", "r"}, s.work);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(has(r.out, h.expect), h.expect << ": " << r.out);
    BOOST_TEST(pngs(s.work / "r").empty(), r.out);
  }
  // The whole run plots.
  std::ofstream(s.work / "r" / "timeseries.csv", std::ios::binary | std::ios::trunc) << csv;
  std::ofstream(s.work / "r" / "summary.json", std::ios::binary | std::ios::trunc) << sum;
  if (gnuplot_available()) BOOST_TEST(run_pcsim({"plot", "r"}, s.work).status == 0);
}

// output.format = "npy": the run writes timeseries.npy and no timeseries.csv; the header's row
// count, written at the end, is the CSV run's number of rows and the data fill the file exactly
// (22 rows of the pendulum's records); a CSV run into the same directory afterwards replaces it
// (the directory holds one run's files). pcsim plot draws the .npy run from the same data as the
// CSV run: its plots.csv (the rows gnuplot reads) is byte for byte the CSV run's timeseries.csv,
// its script the same but for that name, its figures the same bytes; without gnuplot it says so
// and leaves nothing behind.
BOOST_AUTO_TEST_CASE(npy_output_replaces_the_csv_and_plots_from_the_same_data) {
  Scratch s("files_npy");
  std::ofstream(s.work / "p.toml") << files_test::pendulum_case("p", 0.2);
  const Result r = run_pcsim({"run", "p.toml", "--set", "output.format=npy"}, s.work);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  BOOST_TEST(has(r.out, "timeseries.npy"), r.out);
  const fs::path out = s.work / "out" / "p";
  BOOST_TEST(!fs::exists(out / "timeseries.csv"));
  const std::string npy = pcsim_test::read(out / "timeseries.npy");
  BOOST_TEST_REQUIRE(npy.size() > 64u);
  BOOST_TEST(npy.compare(0, 6, "\x93NUMPY") == 0);
  const std::size_t header = 10 + (static_cast<unsigned char>(npy[8]) | static_cast<unsigned char>(npy[9]) << 8);
  BOOST_TEST(header % 64 == 0u);
  const std::string dict = npy.substr(10, header - 10);
  BOOST_TEST(has(dict, "'shape': (                  21,)"), dict);  // t = 0, 0.01, ..., 0.2
  const long fields = std::count(dict.begin(), dict.end(), '(') - 1;  // '(' of each field, and of shape
  BOOST_TEST(npy.size() == header + 21u * 8u * static_cast<std::size_t>(fields));
  const Result csv_run = run_pcsim({"run", "p.toml", "--out", "csv"}, s.work);
  BOOST_TEST_REQUIRE(csv_run.status == 0, csv_run.out);
  const Result missing = pcsim_test::sh("PATH=/nonexistent '" + pcsim_test::exe() + "' plot out/p", s.work);
  BOOST_TEST(missing.status == 2, missing.out);
  BOOST_TEST(has(missing.out, "needs gnuplot"), missing.out);
  BOOST_TEST(pngs(out).empty());
  BOOST_TEST(!fs::exists(out / "plots.csv"));
  if (gnuplot_available()) {
    const Result p = run_pcsim({"plot", "out/p"}, s.work), c = run_pcsim({"plot", "csv"}, s.work);
    BOOST_TEST_REQUIRE(p.status == 0, p.out);
    BOOST_TEST_REQUIRE(c.status == 0, c.out);
    BOOST_TEST(pcsim_test::read(out / "plots.csv") == pcsim_test::read(s.work / "csv" / "timeseries.csv"));
    std::string script = pcsim_test::read(out / "plots.gp");
    for (auto at = script.find("'plots.csv'"); at != std::string::npos; at = script.find("'plots.csv'", at))
      script.replace(at, 11, "'timeseries.csv'");
    BOOST_TEST(script == pcsim_test::read(s.work / "csv" / "plots.gp"));
    BOOST_TEST(pngs(out).size() == pngs(s.work / "csv").size());
    BOOST_TEST(!pngs(out).empty());
    for (const fs::path& png : pngs(out))  // the same figures, drawn from the same bytes
      BOOST_TEST((pcsim_test::read(png) == pcsim_test::read(s.work / "csv" / png.filename())), png);
    for (const auto& e : fs::directory_iterator(out))  // no temporary left
      BOOST_TEST((e.path().filename().string()[0] != '.' || e.path().filename() == ".pcsim-output"), e.path());
  }
  const Result c = run_pcsim({"run", "p.toml"}, s.work);
  BOOST_TEST_REQUIRE(c.status == 0, c.out);
  BOOST_TEST(fs::exists(out / "timeseries.csv"));
  BOOST_TEST(!fs::exists(out / "timeseries.npy"));
  BOOST_TEST(s.user_files_intact());
}

// A timeseries.npy that is not what the run wrote (cut off in its header or its rows, another
// dtype, Fortran order, a 2-D shape, a row count the file does not hold or whose byte count
// overflows): pcsim plot and pcsim animate exit 2 naming the file and what they expected, and
// write nothing (no figure, no plots.csv, no page).
BOOST_AUTO_TEST_CASE(plot_and_animate_refuse_a_bad_npy_naming_it_and_write_nothing) {
  Scratch s("files_npy_bad");
  std::ofstream(s.work / "p.toml") << files_test::pendulum_case("p", 0.2);
  BOOST_TEST_REQUIRE(run_pcsim({"run", "p.toml", "--set", "output.format=npy", "--out", "r"}, s.work).status == 0);
  const fs::path f = s.work / "r" / "timeseries.npy";
  const std::string good = pcsim_test::read(f);
  const std::size_t header = 10 + (static_cast<unsigned char>(good[8]) | static_cast<unsigned char>(good[9]) << 8);
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string b = good;
    const auto at = b.find(from);
    BOOST_TEST_REQUIRE(at < header, from);
    b.replace(at, from.size(), to + std::string(from.size() - to.size(), ' '));  // the header's length kept
    return b;
  };
  struct Bad {
    std::string bytes, expect;
  };
  const std::vector<Bad> cases = {
      {good.substr(0, 7), "cut off within its first 10 bytes"},
      {good.substr(0, header / 2), "is cut off after"},
      {good.substr(0, good.size() - 5), "the file holds"},
      {replaced("('x', '<f8')", "('x', '<i8')"), "expected the type '<f8'"},
      {replaced("'fortran_order': False", "'fortran_order': True"), "'fortran_order': False"},
      {replaced("(                  21,)", "(21, 3)"), "one dimension (rows,)"},
      {replaced("(                  21,)", "(22,)"), "header says 22 rows"},
      {replaced("(                  21,)", "(18446744073709551615,)"), "header says 18446744073709551615 rows"},
  };
  for (const auto& b : cases)
    for (const char* cmd : {"plot", "animate"}) {
      std::ofstream(f, std::ios::binary | std::ios::trunc) << b.bytes;
      const Result r = run_pcsim({cmd, "r"}, s.work);
      BOOST_TEST(r.status == 2, cmd << ": " << r.out);
      BOOST_TEST(has(r.out, "r/timeseries.npy: "), cmd << ": " << r.out);
      BOOST_TEST(has(r.out, b.expect), cmd << ": " << b.expect << " | " << r.out);
      BOOST_TEST(pngs(s.work / "r").empty());
      BOOST_TEST(!fs::exists(s.work / "r" / "plots.csv"));
      BOOST_TEST(!fs::exists(s.work / "r" / "animation.html"));
    }
  BOOST_TEST(s.user_files_intact());
}

// pcsim steady honours output.format = "npy" as run does: its one period is timeseries.npy (no
// timeseries.csv), the same rows as the CSV steady run's (plot's plots.csv, the rows read back,
// is byte for byte that run's timeseries.csv), the directory can be written again, and the
// report names the file.
BOOST_AUTO_TEST_CASE(steady_writes_its_period_as_npy_with_output_format_npy) {
  Scratch s("files_steady_npy");
  const std::string duffing = std::string(PCSIM_SOURCE_DIR) + "/tests/steady/duffing.toml";
  const Result n = run_pcsim({"steady", duffing, "--set", "output.format=npy", "--out", "n"}, s.work);
  BOOST_TEST_REQUIRE(n.status == 0, n.out);
  BOOST_TEST(has(n.out, "n/timeseries.npy"), n.out);
  BOOST_TEST(fs::exists(s.work / "n" / "timeseries.npy"));
  BOOST_TEST(!fs::exists(s.work / "n" / "timeseries.csv"));
  const Result again = run_pcsim({"steady", duffing, "--set", "output.format=npy", "--out", "n"}, s.work);
  BOOST_TEST_REQUIRE(again.status == 0, again.out);
  const Result c = run_pcsim({"steady", duffing, "--out", "c"}, s.work);
  BOOST_TEST_REQUIRE(c.status == 0, c.out);
  BOOST_TEST(fs::exists(s.work / "c" / "timeseries.csv"));
  if (gnuplot_available()) {
    const Result p = run_pcsim({"plot", "n"}, s.work);
    BOOST_TEST_REQUIRE(p.status == 0, p.out);
    BOOST_TEST(pcsim_test::read(s.work / "n" / "plots.csv") == pcsim_test::read(s.work / "c" / "timeseries.csv"));
  }
  BOOST_TEST(s.user_files_intact());
}
