// A generator of hostile names over run, plot and sweep (issue 19): case names and --out /
// plot directory names built from quotes, backquotes, line breaks and other control
// characters, separators, dots, gnuplot and shell syntax, unicode and long runs. After every
// command the invariants hold: the exit status is 0 or 2; no file named PWNED exists; nothing
// was created outside the scratch directory; the user's files seeded there are unchanged; and a
// refused command created no output directory.
// CTest runs a fixed seed for a few seconds (PCSIM_FUZZ_NAMES=<iterations>, PCSIM_FUZZ_SEED=<n>
// for longer runs by hand: build/test_files_fuzz with PCSIM_EXE set).
#define BOOST_TEST_MODULE sim_files_fuzz
#include <boost/test/unit_test.hpp>

#include "../support/files_util.hpp"

#include <algorithm>

#include "common/gnuplot.hpp"

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using files_test::run_pcsim;
using pcsim_test::Result;

namespace {

const std::vector<std::string> kPieces = {
    "x", "ab", "run", "'", "''", "''''", "\"", "`", "`touch PWNED`", "; system(\"touch PWNED\"); #",
    "'; system('touch PWNED'); print '", "$(touch PWNED)", "|touch PWNED", "\n", "\r", "\t",
    std::string(1, '\0'), "\x01", "\x1b[31m", "\x7f", "/", "\\", ".", "..", "../", "-", "--out", "@a", "%s",
    "Müller", "∑", "\xe2\x80\xae", "\xff", " ", "#", "*", "?", "~", "{}", "[x]", "=", ","};

std::string hostile_name(std::mt19937& rng) {
  std::uniform_int_distribution<int> count(1, 5), pick(0, static_cast<int>(kPieces.size()) - 1), rare(0, 19);
  if (rare(rng) == 0) return std::string(std::uniform_int_distribution<int>(100, 300)(rng), 'n');
  std::string s;
  for (int i = count(rng); i > 0; --i) s += kPieces[static_cast<std::size_t>(pick(rng))];
  return s;
}

}  // namespace

BOOST_AUTO_TEST_CASE(hostile_names_over_run_plot_and_sweep_keep_the_invariants) {
  const char* it_env = std::getenv("PCSIM_FUZZ_NAMES");
  const char* seed_env = std::getenv("PCSIM_FUZZ_SEED");
  const int iterations = it_env ? std::atoi(it_env) : 24;
  std::mt19937 rng(seed_env ? static_cast<unsigned>(std::atoi(seed_env)) : 19u);
  files_test::Scratch s("files_fuzz");
  const bool gnuplot = pcsim_test::sh("command -v gnuplot >/dev/null").status == 0;
  int ran = 0, refused = 0, plotted = 0;
  for (int i = 0; i < iterations; ++i) {
    const std::string name = hostile_name(rng);
    const int mode = std::uniform_int_distribution<int>(0, 3)(rng);
    std::vector<std::string> cmd;
    std::string out_dir;  // the directory the command would write, relative to work/
    if (mode == 0 || mode == 2) {  // the name as the case name
      std::ofstream(s.work / "c.toml", std::ios::binary | std::ios::trunc) << files_test::pendulum_case(name);
      cmd = {"run", "c.toml"};
      out_dir = "out/" + name;
      if (mode == 2) {
        std::ofstream(s.work / "c.toml", std::ios::binary | std::ios::trunc)
            << "name = " << files_test::toml_string(name) << "\nmodel = \"sieve\"\n[solver]\nt_end = 0.02\n";
        cmd = {"sweep", "c.toml", "--vary", "parameters.omega=260", "-j", "1"};
        out_dir = "out/" + name + "-sweep";
      }
    } else {  // the name as a directory the user gives (one path component: no '/')
      std::string leaf = name;
      for (char& c : leaf)
        if (c == '/' || c == '\0') c = '_';
      std::ofstream(s.work / "c.toml", std::ios::binary | std::ios::trunc) << files_test::pendulum_case("c");
      cmd = {"run", "c.toml", "--out", leaf};
      out_dir = leaf;
    }
    const Result r = run_pcsim(cmd, s.work);
    BOOST_TEST((r.status == 0 || r.status == 2), cmd[0] << " with " << files_test::toml_string(name) << ": " << r.out);
    bool in_work = true;  // no component . or .. (which must be refused)
    for (const auto& part : fs::path(out_dir)) in_work = in_work && part != "." && part != "..";
    if (r.status == 0) {
      ++ran;
      BOOST_TEST(in_work, files_test::toml_string(name));
      if (in_work && cmd[0] == "run") BOOST_TEST(fs::exists(s.work / out_dir / ".pcsim-output"));
      if (gnuplot && cmd[0] == "run" && (mode == 3 || i % 3 == 0)) {
        const Result p = run_pcsim({"plot", "--", out_dir}, s.work);
        BOOST_TEST(p.status == 0, files_test::toml_string(name) << ": " << p.out);
        ++plotted;
      }
    } else {
      ++refused;
    }
    BOOST_TEST(!files_test::pwned(s.path), files_test::toml_string(name));
    BOOST_TEST(s.user_files_intact(), files_test::toml_string(name));
    BOOST_TEST(s.nothing_outside(), files_test::toml_string(name));
  }
  BOOST_TEST_MESSAGE("hostile names: " << iterations << " commands, " << ran << " ran, " << refused
                                       << " refused, " << plotted << " plotted");
  BOOST_TEST(ran > 0);
  BOOST_TEST(refused > 0);
}

// The quoting itself, against the real gnuplot: every generated string (any bytes but NUL),
// quoted by gnuplot_quoted, is one string literal to gnuplot: a script printing all of them
// runs without an error (nothing ended a string early) and creates no PWNED; and a quoted string
// holds no quote but its two delimiters and no control character.
BOOST_AUTO_TEST_CASE(gnuplot_quoted_strings_cannot_end_early) {
  std::mt19937 rng(7);
  std::string script;
  for (int i = 0; i < 300; ++i) {
    std::string s = hostile_name(rng);
    const std::string q = pcsim::gnuplot_quoted(s);
    BOOST_TEST(std::count(q.begin(), q.end(), '\'') == 2, q);
    BOOST_TEST(q.front() == '\'');
    BOOST_TEST(q.back() == '\'');
    BOOST_TEST(std::none_of(q.begin(), q.end(), [](char c) {
      const unsigned char u = static_cast<unsigned char>(c);
      return u < 0x20 || u == 0x7f || c == '`';
    }), q);
    script += "print " + q + "\n";
  }
  if (pcsim_test::sh("command -v gnuplot >/dev/null").status != 0) return;
  pcsim_test::TempDir d("gp_quote");
  BOOST_TEST(pcsim::run_gnuplot(d.path, script, "gnuplot.log") == 0, pcsim_test::read(d.path / "gnuplot.log"));
  BOOST_TEST(!files_test::pwned(d.path));
}
