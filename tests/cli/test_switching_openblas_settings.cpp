// Bit-for-bit reproducible under any OpenBLAS setting (issues 12 and 14): the rocking block
// needs an LCP at each impact, so pcsim loads the Siconos plugin (and the OpenBLAS it links)
// there. The run is repeated with OPENBLAS_NUM_THREADS = 1 and 2 and OPENBLAS_CORETYPE =
// Haswell, Sandybridge, Prescott (and unset); events.csv, timeseries.csv and summary.json must
// be byte-identical (numbers are written shortest-round-trip, so equal bytes are equal bits),
// wall time aside. pcsim sets OPENBLAS_NUM_THREADS=1 itself before loading the plugin, and its
// own BLAS/LAPACK are the reference libraries, to which Siconos's calls bind as well.
#define BOOST_TEST_MODULE switching_openblas_settings
#include <boost/test/unit_test.hpp>

#include <regex>
#include <vector>

#include "switching_cli.hpp"

using namespace switching_cli;

namespace {
std::string without_wall_time(std::string summary) {
  return std::regex_replace(summary, std::regex("\"wall_seconds\": [^,\\n]*"), "\"wall_seconds\": 0");
}
}  // namespace

BOOST_AUTO_TEST_CASE(rocking_block_is_bit_identical_under_every_openblas_setting) {
  TempDir dir("openblas");
  const std::vector<std::string> settings = {
      "",
      "OPENBLAS_NUM_THREADS=1",
      "OPENBLAS_NUM_THREADS=2",
      "OPENBLAS_NUM_THREADS=2 OPENBLAS_CORETYPE=Haswell",
      "OPENBLAS_NUM_THREADS=1 OPENBLAS_CORETYPE=Sandybridge",
      "OPENBLAS_NUM_THREADS=2 OPENBLAS_CORETYPE=Prescott",
      "OMP_NUM_THREADS=2 GOTO_NUM_THREADS=2 OPENBLAS_CORETYPE=Prescott",
  };
  std::string events0, series0, summary0;
  for (std::size_t i = 0; i < settings.size(); ++i) {
    const fs::path out = dir.path / ("run" + std::to_string(i));
    const Result r = pcsim("run cases/rocking_block.toml --out '" + out.string() + "'", settings[i]);
    BOOST_TEST_CONTEXT("env: " << settings[i]) {
      BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
      BOOST_TEST(r.out.find("LCPs solved by Siconos") != std::string::npos);  // the plugin ran
      const std::string events = read(out / "events.csv"), series = read(out / "timeseries.csv"),
                        summary = without_wall_time(read(out / "summary.json"));
      if (i == 0) {
        events0 = events;
        series0 = series;
        summary0 = summary;
        BOOST_TEST(events.size() > 1000u);
        continue;
      }
      BOOST_TEST((events == events0), "events.csv differs");
      BOOST_TEST((series == series0), "timeseries.csv differs");
      BOOST_TEST((summary == summary0), "summary.json differs");
    }
  }
}
