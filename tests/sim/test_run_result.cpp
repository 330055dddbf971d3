// The typed run result (sim/result.hpp): summary.json is to_json of it, its fields say what
// the file says, and result_from_json reads a summary back to the same result.
#define BOOST_TEST_MODULE run_result
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "sim/case.hpp"
#include "sim/client.hpp"
#include "sim/run.hpp"

using namespace pcsim;
using namespace pcsim::sim;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("pcsim_run_result_" + std::to_string(::getpid()));
  TempDir() { fs::remove_all(path); }
  ~TempDir() { fs::remove_all(path); }
};

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return nlohmann::json::parse(in);
}

/// The written summary and the result's JSON, both without the wall-clock time.
void check_written(const RunResult& r, const fs::path& dir) {
  nlohmann::json written = read_json(dir / "summary.json"), typed = to_json(r);
  written["stats"].erase("wall_seconds");
  typed["stats"].erase("wall_seconds");
  BOOST_TEST(written.dump() == typed.dump());
}

/// Every scalar of summary.json by its dotted path (array elements by index).
void leaves(const nlohmann::json& j, const std::string& path,
            std::vector<std::pair<std::string, nlohmann::json>>& out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) leaves(v, path.empty() ? k : path + "." + k, out);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) leaves(j[i], path + "." + std::to_string(i), out);
  } else {
    out.emplace_back(path, j);
  }
}

/// RunResult::value says what to_json says, for every scalar (non-finite numbers as null).
void check_values(const RunResult& r) {
  std::vector<std::pair<std::string, nlohmann::json>> all;
  leaves(to_json(r), "", all);
  BOOST_TEST(all.size() > 20u);
  for (const auto& [path, v] : all) {
    const nlohmann::json expected =
        v.is_number_float() && !std::isfinite(v.get<double>()) ? nlohmann::json(nullptr) : v;
    const nlohmann::json got = r.value(path);
    const nlohmann::json got_or_null =
        got.is_number_float() && !std::isfinite(got.get<double>()) ? nlohmann::json(nullptr) : got;
    BOOST_TEST(got_or_null.dump() == expected.dump(), path);
  }
  BOOST_TEST(r.value("no_such_key").is_null());
  BOOST_TEST(r.value("extremes").is_null());  // not a scalar
}

}  // namespace

BOOST_AUTO_TEST_CASE(fields_say_what_summary_json_says) {
  TempDir d;
  const Case c = load_case(fs::path(PCSIM_SOURCE_DIR) / "cases" / "slider_crank.toml",
                           {{"solver.t_end", "0.3"}});
  RunOptions o;
  o.out_dir = d.path / "out";
  const RunResult r = run_case(c, o);
  check_written(r, *o.out_dir);
  BOOST_TEST(r.case_name == "slider_crank");
  BOOST_TEST(r.complete);
  BOOST_TEST(!r.failure.has_value());
  BOOST_TEST(r.t_end == 0.3);
  BOOST_TEST(r.window_end == 0.3);
  BOOST_TEST(r.columns.front() == "t");
  BOOST_TEST(r.accuracy.reliable);
  // Every value column has its extremes, by name; the time and residual columns have none.
  const std::string phi = c.model->coordinates().front();
  const ColumnExtremes& e = r.extreme(phi);
  BOOST_TEST(e.min <= e.max);
  BOOST_TEST(e.amplitude() == 0.5 * (e.max - e.min));
  BOOST_TEST(e.t_min >= r.window_start);
  BOOST_TEST(e.t_max <= r.window_end);
  BOOST_TEST(r.extremes.count("R_" + phi) == 1u);
  BOOST_TEST(r.extremes.count("t") == 0u);
  BOOST_CHECK_THROW(r.extreme("no_such_column"), std::out_of_range);
  BOOST_TEST(r.q_end.at(phi) == to_json(r)["q_end"][phi].get<double>());
  BOOST_TEST(r.stats.steps > 0);
  BOOST_TEST(r.additions.empty());  // the slider-crank has no client
  check_values(r);
}

// A switching run (its "switching" object) reads back to the same result and report.
BOOST_AUTO_TEST_CASE(from_json_reads_a_summary_back) {
  TempDir d;
  const Case c = load_case(fs::path(PCSIM_SOURCE_DIR) / "cases" / "bouncing_ball.toml",
                           {{"solver.t_end", "0.5"}});
  RunOptions o;
  o.out_dir = d.path / "out";
  const RunResult r = run_case(c, o);
  BOOST_TEST(!r.switching.is_null());
  check_written(r, *o.out_dir);
  const nlohmann::json s = to_json(r);
  const RunResult back = result_from_json(s, timeseries_columns(c));
  BOOST_TEST(to_json(back).dump() == s.dump());
  BOOST_TEST(back.columns == r.columns);
  BOOST_TEST(human_report(c, back) == human_report(c, r));
  check_values(r);
}

namespace {

// An application in small: counts the steps it watched, adds them and the largest tension to
// the result, and reports them.
class StepCounter : public ClientMonitor {
 public:
  bool observe(const mech::StepView&) override {
    ++steps_;
    return true;
  }
  void finish(const mech::SimulationResult&, RunResult& result) override {
    result.additions["steps_watched"] = steps_;
    result.additions["tension"] = {{"max", result.extreme("tension").max}};
  }

 private:
  long steps_ = 0;
};

class CountingClient : public Client {
 public:
  std::unique_ptr<ClientMonitor> monitor(const Case&, const Setup&) const override {
    return std::make_unique<StepCounter>();
  }
  std::string report(const Case&, const RunResult& r) const override {
    return "watched " + std::to_string(r.additions.at("steps_watched").get<long>()) + " steps\n";
  }
  std::map<std::string, double> derived_columns(const RunResult& r, const Case&) const override {
    return {{"tension_max", r.additions.at("tension").at("max").get<double>()}};
  }
};

}  // namespace

// A client's additions go into summary.json, its report and derived columns read the result.
BOOST_AUTO_TEST_CASE(a_client_adds_to_the_result) {
  register_client("pendulum", std::make_shared<CountingClient>());
  const Case c = load_case_text(R"(model = "pendulum"
[initial]
x = 1.0
y = 0.0
[solver]
t_end = 0.2
)", "pendulum.toml");
  const RunResult r = run_case(c);
  BOOST_TEST(r.additions.at("steps_watched").get<long>() == r.stats.accepted + 1);  // and t0
  BOOST_TEST(r.additions.at("tension").at("max").get<double>() == r.extreme("tension").max);
  const nlohmann::json s = to_json(r);
  BOOST_TEST(s.at("steps_watched") == r.additions.at("steps_watched"));
  BOOST_TEST(human_report(c, r) == "watched " + std::to_string(r.stats.accepted + 1) + " steps\n");
  BOOST_TEST(c.client->derived_columns(r, c).at("tension_max") == r.extreme("tension").max);
  const RunResult back = result_from_json(s, timeseries_columns(c));
  BOOST_TEST(back.additions == r.additions);
  check_values(r);
  BOOST_TEST(r.value("tension.max").get<double>() == r.extreme("tension").max);
  register_client("pendulum", nullptr);
}

// ---- Deferred monitors ----------------------------------------------------------------------
// Issue 23: run_case's generic monitor (the time-series rows and the window extremes) observes
// the steps on a thread of its own (mech::DeferredObserver). Oracle: the same case observed in
// place (RunOptions::deferred_monitor = false): timeseries.csv byte for byte, summary.json
// (without its wall-clock time) and the rows kept in memory (the Python module's) the same, on
// models of every kind: planar and spatial, redundant, stiff (Radau: its dense output's copy),
// the DAE form, with projection and without, and a switching case (observed in place).

namespace {

struct NumberedTempDir {
  fs::path path;
  NumberedTempDir() {
    static int n = 0;
    path = fs::temp_directory_path() /
           ("pcsim_deferred_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::remove_all(path);
  }
  ~NumberedTempDir() {
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
      NumberedTempDir in_place, deferred;
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
