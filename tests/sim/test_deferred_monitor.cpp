// Issue 23: run_case's generic monitor (the time-series rows and the window extremes) observes
// the steps on a thread of its own (mech::DeferredObserver). Oracle: the same case observed in
// place (RunOptions::deferred_monitor = false): timeseries.csv byte for byte, summary.json
// (without its wall-clock time) and the rows kept in memory (the Python module's) the same, on
// models of every kind: planar and spatial, redundant, stiff (Radau: its dense output's copy),
// the DAE form, with projection and without, and a switching case (observed in place).
#define BOOST_TEST_MODULE deferred_monitor
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

#include "sim/case.hpp"
#include "sim/run.hpp"

using namespace pcsim;
using namespace pcsim::sim;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    static int n = 0;
    path = fs::temp_directory_path() /
           ("pcsim_deferred_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::remove_all(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string summary_without_wall(const fs::path& dir) {
  nlohmann::json s = nlohmann::json::parse(file_text(dir / "summary.json"));
  s["stats"].erase("wall_seconds");
  return s.dump();
}

}  // namespace

BOOST_AUTO_TEST_CASE(deferred_and_in_place_monitors_write_the_same_files) {
  struct Run { const char* file; std::vector<Override> set; };
  const std::vector<Run> runs = {
      {"slider_crank.toml", {{"solver.t_end", "0.3"}}},
      {"slider_crank.toml", {{"solver.t_end", "0.3"}, {"solver.form", "dae"}}},
      {"andrews_squeezer.toml", {{"solver.t_end", "0.01"}, {"solver.method", "radau"}}},
      {"double_pendulum_bodies.toml", {{"solver.t_end", "0.5"}}},
      {"parallelogram_third_crank.toml", {{"solver.t_end", "0.3"}}},  // redundant
      {"tumbling_body.toml", {{"solver.t_end", "0.3"}}},    // spatial, Euler parameters
      {"rolling_coin.toml", {{"solver.t_end", "0.3"}}},     // nonholonomic
      {"bouncing_ball.toml", {{"solver.t_end", "0.5"}}},    // switching: observed in place
  };
  for (const Run& r : runs) {
    BOOST_TEST_CONTEXT(r.file) {
      const Case c = load_case(fs::path(PCSIM_SOURCE_DIR) / "cases" / r.file, r.set);
      TempDir in_place, deferred;
      Kept kept_in_place, kept_deferred;
      RunOptions o;
      o.out_dir = in_place.path;
      o.keep = &kept_in_place;
      o.deferred_monitor = false;
      const RunResult a = run_case(c, o);
      o.out_dir = deferred.path;
      o.keep = &kept_deferred;
      o.deferred_monitor = true;
      const RunResult b = run_case(c, o);
      BOOST_TEST(a.complete);
      BOOST_TEST(b.complete);
      if (c.setup.method == OdeMethod::radau) BOOST_TEST(b.methods_used == "radau");
      const std::string ta = file_text(in_place.path / "timeseries.csv");
      BOOST_TEST((ta == file_text(deferred.path / "timeseries.csv")));
      BOOST_TEST(ta.size() > 200u);
      BOOST_TEST(summary_without_wall(in_place.path) == summary_without_wall(deferred.path));
      BOOST_TEST((kept_in_place.rows == kept_deferred.rows));
      BOOST_TEST(!kept_in_place.rows.empty());
    }
  }
}
