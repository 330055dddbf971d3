// pcsim animate as a user runs it: every case in cases/ animates after pcsim run; bad input
// (not a directory, not a run, a failed or half-written run, a run being written, a model with
// nothing to draw) exits 2 and writes nothing; --video writes the named file (mp4 or gif) and
// refuses a file pcsim did not write; the video's rasterizer puts points where the page does.
#define BOOST_TEST_MODULE animate_cli
#include <boost/test/unit_test.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "animate/scene.hpp"
#include "animate/video.hpp"
#include "animate_util.hpp"
#include "../support/build_tree.hpp"

using namespace animate_test;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = PCSIM_SOURCE_DIR;

std::set<std::string> listing(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.insert(fs::relative(e.path(), dir).string());
  return out;
}

// A short run of each case: the sieve cases 0.3 s, the others at most 1 s; under the
// sanitizers (the Debug build, where the spatial and redundant models cost tens of milliseconds
// per evaluation) every case 0.2 s: the page is what is tested, not the motion. Never longer
// than the case itself (Andrews' squeezer runs 0.03 s; at 1 s its crank spins up to 45,000 steps).
std::string short_run(const fs::path& file) {
  const std::string name = file.stem().string();
  double limit = pcsim_test::slow_build() ? 0.2 : name.rfind("sieve", 0) == 0 ? 0.3 : 1.0;
  const toml::table t = toml::parse_file(file.string());
  limit = std::min(limit, t["solver"]["t_end"].value_or(limit));
  std::ostringstream os;
  os.precision(17);
  os << "--set solver.t_end=" << limit;
  return os.str();
}

// Under the sanitizers, one case of each kind of drawing (the sieve's own, contact modes, a
// planar body model, spatial models drawn by hand and by default, Euler parameters): loading a
// spatial model costs seconds there, and the drawing code is the same for every case. The two
// Release builds of CI animate every case.
const std::set<std::string> kSanitizedCases = {"sieve_1995", "sieve_1995_hopping", "double_pendulum_bodies",
                                               "bouncing_ball", "slider_crank_spatial", "engine_mount_bushing"};

}  // namespace

BOOST_AUTO_TEST_CASE(every_case_animates_after_pcsim_run) {
  pcsim_test::TempDir scratch("animate_cases");
  int n = 0;
  for (const auto& name : kSanitizedCases) BOOST_TEST_REQUIRE(fs::exists(kSource / "cases" / (name + ".toml")), name);
  for (const auto& e : fs::directory_iterator(kSource / "cases")) {
    if (e.path().extension() != ".toml") continue;
    const std::string name = e.path().stem().string();
    if (!PCSIM_WITH_SIEVE && name.rfind("sieve", 0) == 0) continue;
    if (pcsim_test::slow_build() && kSanitizedCases.count(name) == 0) continue;
    BOOST_TEST_CONTEXT(name) {
      const fs::path out = scratch.path / name;
      const Result r = run_pcsim("run '" + e.path().string() + "' --out '" + out.string() + "' " + short_run(e.path()), kSource);
      BOOST_TEST_REQUIRE(r.status == 0, r.out);
      BOOST_TEST(fs::exists(out / "model.toml"));
      const Result a = run_pcsim("animate '" + out.string() + "'", kSource);
      BOOST_TEST(a.status == 0, a.out);
      const std::string html = pcsim_test::read(out / "animation.html");
      BOOST_TEST(pcsim_test::has(html, "default-src 'none'"));
      BOOST_TEST(!pcsim_test::has(html, "http://"));
      BOOST_TEST(!pcsim_test::has(html, "https://"));
      BOOST_TEST(!pcsim_test::has(html, "<script src"));
      // the run can be run again into the same directory (animation.html is pcsim's file):
      // once, on the first case
      if (n == 0) {
        const Result again = run_pcsim("run '" + e.path().string() + "' --out '" + out.string() + "' " + short_run(e.path()), kSource);
        BOOST_TEST(again.status == 0, again.out);
      }
      ++n;
    }
  }
  BOOST_TEST(n >= (pcsim_test::slow_build() ? (PCSIM_WITH_SIEVE ? 6 : 4) : PCSIM_WITH_SIEVE ? 8 : 5));
}

// output.format = "npy": pcsim animate reads timeseries.npy to the same rows as the CSV run's
// timeseries.csv, so the page is byte for byte the CSV run's (every number embedded in it, the
// contact modes of a switching run read back from their labels).
BOOST_AUTO_TEST_CASE(an_npy_run_animates_to_the_page_of_its_csv_run) {
  pcsim_test::TempDir scratch("animate_npy");
  std::ofstream(scratch.path / "pend_case.toml")
      << "model = \"pendulum\"\n[initial]\nx = 0.6\ny = -0.8\n[solver]\nt_end = 0.5\n";
  for (const fs::path& file : {scratch.path / "pend_case.toml", kSource / "cases" / "bouncing_ball.toml"}) {
    BOOST_TEST_CONTEXT(file.stem().string()) {
      std::string page[2];
      for (int npy = 0; npy < 2; ++npy) {
        const fs::path out = scratch.path / (file.stem().string() + (npy ? "_npy" : "_csv"));
        const Result r = run_pcsim("run '" + file.string() + "' --out '" + out.string() + "' " + short_run(file) +
                                       (npy ? " --set output.format=npy" : ""),
                                   scratch.path);
        BOOST_TEST_REQUIRE(r.status == 0, r.out);
        BOOST_TEST(fs::exists(out / (npy ? "timeseries.npy" : "timeseries.csv")));
        const Result a = run_pcsim("animate '" + out.string() + "'", scratch.path);
        BOOST_TEST_REQUIRE(a.status == 0, a.out);
        page[npy] = pcsim_test::read(out / "animation.html");
      }
      BOOST_TEST(!page[0].empty());
      BOOST_TEST((page[0] == page[1]));
    }
  }
}

BOOST_AUTO_TEST_CASE(bad_input_exits_2_and_writes_nothing) {
  pcsim_test::TempDir scratch("animate_bad");
  const fs::path w = scratch.path;
  // not a directory
  std::ofstream(w / "file.txt") << "x";
  Result r = run_pcsim("animate '" + (w / "file.txt").string() + "'", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "not a directory"), r.out);
  r = run_pcsim("animate '" + (w / "absent").string() + "'", w);
  BOOST_TEST(r.status == 2, r.out);
  // a directory that is not a run
  fs::create_directories(w / "mine");
  std::ofstream(w / "mine" / "notes.txt") << "mine";
  r = run_pcsim("animate '" + (w / "mine").string() + "'", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "not the output directory of `pcsim run`"), r.out);
  BOOST_TEST(listing(w / "mine") == std::set<std::string>{"notes.txt"});

  // a model with nothing to draw: the message names what to add and where
  const std::string model = R"TOML(
[model]
name = "plain"
coordinates = ["x"]
[model.parameters]
k = 1.0
[model.energy]
kinetic = "0.5*x_d^2"
potential = "0.5*k*x^2"
)TOML";
  std::ofstream(w / "plain.toml") << model;
  std::ofstream(w / "plain_case.toml") << "model = \"plain.toml\"\n[initial]\nx = 1\n[solver]\nt_end = 1\n";
  r = run_pcsim("run plain_case.toml --out run_plain", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  auto before = listing(w / "run_plain");
  r = run_pcsim("animate run_plain", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "nothing to draw"), r.out);
  BOOST_TEST(pcsim_test::has(r.out, "[model.draw]"), r.out);
  BOOST_TEST(pcsim_test::has(r.out, "plain.toml"), r.out);
  BOOST_TEST(listing(w / "run_plain") == before);

  // a run that is being written (its lock held)
  std::ofstream(w / "pend_case.toml") << "model = \"pendulum\"\n[initial]\nx = 0.6\ny = -0.8\n[solver]\nt_end = 0.5\n";
  r = run_pcsim("run pend_case.toml --out run_pend", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  before = listing(w / "run_pend");
  {
    const int fd = ::open((w / ".run_pend.lock").c_str(), O_RDWR | O_CREAT, 0644);
    BOOST_TEST_REQUIRE(fd >= 0);
    BOOST_TEST_REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
    r = run_pcsim("animate run_pend", w);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(pcsim_test::has(r.out, "in use"), r.out);
    ::close(fd);
    fs::remove(w / ".run_pend.lock");
  }
  BOOST_TEST(listing(w / "run_pend") == before);

  // a failed or half-written run: summary.json not complete, a torn time series, no model.toml
  const auto copy_run = [&](const std::string& name) {
    fs::copy(w / "run_pend", w / name, fs::copy_options::recursive);
    return w / name;
  };
  {
    const fs::path d = copy_run("failed");
    std::string s = pcsim_test::read(d / "summary.json");
    s.replace(s.find("\"complete\": true"), 16, "\"complete\": false");
    std::ofstream(d / "summary.json") << s;
    before = listing(d);
    r = run_pcsim("animate failed", w);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(pcsim_test::has(r.out, "not complete"), r.out);
    BOOST_TEST(listing(d) == before);
  }
  {
    const fs::path d = copy_run("torn");
    std::string csv = pcsim_test::read(d / "timeseries.csv");
    csv.resize(csv.size() - 7);
    std::ofstream(d / "timeseries.csv") << csv;
    before = listing(d);
    r = run_pcsim("animate torn", w);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(pcsim_test::has(r.out, "torn"), r.out);
    BOOST_TEST(listing(d) == before);
  }
  {
    const fs::path d = copy_run("nomodel");
    fs::remove(d / "model.toml");
    r = run_pcsim("animate nomodel", w);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(pcsim_test::has(r.out, "model.toml"), r.out);
    BOOST_TEST(!fs::exists(d / "animation.html"));
  }
  {
    const fs::path d = copy_run("nosummary");
    fs::remove(d / "summary.json");
    r = run_pcsim("animate nosummary", w);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(!fs::exists(d / "animation.html"));
  }
  // bad options
  r = run_pcsim("animate run_pend --frames 1", w);
  BOOST_TEST(r.status == 2, r.out);
  r = run_pcsim("animate run_pend --video out.avi", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, ".mp4 or .gif"), r.out);
  r = run_pcsim("animate run_pend --video nodir/out.mp4", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(!fs::exists(w / "nodir"));
  BOOST_TEST(!fs::exists(w / "run_pend" / "animation.html"));
}

BOOST_AUTO_TEST_CASE(video_writes_the_named_file_and_refuses_a_file_pcsim_did_not_write) {
  BOOST_TEST_REQUIRE(fs::exists("/usr/bin/ffmpeg"), "Debian's ffmpeg is needed (scripts/install-deps.sh)");
  pcsim_test::TempDir scratch("animate_video");
  const fs::path w = scratch.path;
  std::ofstream(w / "pend_case.toml") << "model = \"pendulum\"\n[initial]\nx = 0.6\ny = -0.8\n[solver]\nt_end = 0.4\n";
  Result r = run_pcsim("run pend_case.toml --out run", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  r = run_pcsim("animate run --video clip.mp4 --fps 10", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  const std::string mp4 = pcsim_test::read(w / "clip.mp4");
  BOOST_TEST(mp4.size() > 1000u);
  BOOST_TEST(mp4.substr(4, 4) == "ftyp");
  r = run_pcsim("animate run --video run/animation.gif --fps 10", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  BOOST_TEST(pcsim_test::read(w / "run" / "animation.gif").substr(0, 6) == "GIF89a");
  // pcsim's own video in the run directory is replaced; a user's file never
  r = run_pcsim("animate run --video run/animation.gif --fps 10", w);
  BOOST_TEST(r.status == 0, r.out);
  r = run_pcsim("animate run --video run/clip.mp4", w);  // not a name pcsim writes in a run
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(!fs::exists(w / "run" / "clip.mp4"));
  std::ofstream(w / "mine.mp4") << "my video";
  r = run_pcsim("animate run --video mine.mp4", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "pcsim did not write it"), r.out);
  BOOST_TEST(pcsim_test::read(w / "mine.mp4") == "my video");
  // the clip.mp4 pcsim wrote outside the run directory is not replaced either (pcsim cannot
  // tell it from a user's file)
  r = run_pcsim("animate run --video clip.mp4", w);
  BOOST_TEST(r.status == 2, r.out);
  // nothing but the named files (no temporaries, logs)
  std::set<std::string> expected = {"pend_case.toml", "run", "clip.mp4", "mine.mp4"};
  std::set<std::string> top;
  for (const auto& e : fs::directory_iterator(w)) top.insert(e.path().filename().string());
  BOOST_TEST(top == expected, boost::test_tools::per_element());
}

// The rasterizer of --video and the page draw the same picture: a named point's pixel in a
// 1000 x 600 frame is the page's (within half a pixel), and the frame is inked there.
BOOST_AUTO_TEST_CASE(the_video_rasterizer_draws_points_where_the_page_does) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()));
  pcsim_test::TempDir scratch("animate_raster");
  const fs::path w = scratch.path;
  Result r = run_pcsim("run '" + (kSource / "cases/double_pendulum.toml").string() + "' --out run --set solver.t_end=1", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  r = run_pcsim("animate run", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  const nlohmann::json s = page_state(w / "run" / "animation.html", "t=0.5&mag=1", w);
  BOOST_TEST_REQUIRE(s.is_object());
  const pcsim::animate::Scene scene = pcsim::animate::read_scene(w / "run", 2000);
  const std::size_t f = static_cast<std::size_t>(s["frame"].get<int>());
  BOOST_TEST_REQUIRE(f < scene.t.size());
  BOOST_TEST(scene.t[f] == s["t"].get<double>());
  pcsim::animate::Rasterizer raster(scene, 1000, 600, 1.0);
  const auto& rgb = raster.draw(f);
  for (std::size_t i = 0; i < scene.spec.points.size(); ++i) {
    const auto& p = scene.spec.points[i];
    if (!p.named) continue;
    const auto [x, y] = raster.pixel(f, i);
    BOOST_TEST(std::abs(x - s["pixels"][p.name][0].get<double>()) <= 0.5, p.name);
    BOOST_TEST(std::abs(y - s["pixels"][p.name][1].get<double>()) <= 0.5, p.name);
    const std::size_t at = (static_cast<std::size_t>(y) * 1000 + static_cast<std::size_t>(x)) * 3;
    BOOST_TEST(rgb[at] + rgb[at + 1] + rgb[at + 2] < 3 * 200, p.name);  // inked, not white
  }
  BOOST_TEST(rgb[(5 * 1000 + 995) * 3] == 255);  // a corner stays white
}

// pcsim steady writes one period of the orbit: its page loops that period.
BOOST_AUTO_TEST_CASE(a_steady_state_animates_as_one_looped_period, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  pcsim_test::TempDir scratch("animate_steady");
  const fs::path w = scratch.path;
  Result r = run_pcsim("steady '" + (kSource / "cases/sieve_1995.toml").string() + "' --out steady", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  r = run_pcsim("animate steady", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  const std::string html = pcsim_test::read(w / "steady" / "animation.html");
  BOOST_TEST(pcsim_test::has(html, "\"steady\":true"));
  const pcsim::animate::Scene s = pcsim::animate::read_scene(w / "steady", 2000);
  BOOST_TEST(s.steady);
  BOOST_TEST(std::abs((s.t.back() - s.t.front()) - 2 * M_PI / 280.0) < 1e-9);  // one excitation period
}

// A `pcsim modes` directory (issue 24) animates as its mode shapes: modes writes model.toml
// beside modes.json as runs do, the page carries one cycle per mode; bad modes directories
// (no model.toml, a --vary trace, a model with nothing to draw, a torn modes.json, --video)
// exit 2 and leave the directory as it was.
BOOST_AUTO_TEST_CASE(a_modes_directory_animates_its_mode_shapes_and_bad_ones_exit_2) {
  pcsim_test::TempDir scratch("animate_modes_cli");
  const fs::path w = scratch.path;
  const std::string at_rest = " --set initial.x1=0 --set initial.y1=-1 --set initial.x2=0 --set initial.y2=-1.7";
  const std::string modes_cmd = "modes '" + (kSource / "cases/double_pendulum.toml").string() + "' --out '" +
                                (w / "m").string() + "'" + at_rest;
  Result r = run_pcsim(modes_cmd, kSource);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  BOOST_TEST(pcsim_test::read(w / "m" / "model.toml").rfind("# pcsim modes: the model file ", 0) == 0);
  BOOST_TEST(pcsim_test::has(pcsim_test::read(w / "m" / "model.toml"), "[model.draw]"));
  BOOST_TEST(pcsim_test::has(pcsim_test::read(w / "m" / "modes.json"), "\"parameters\""));
  r = run_pcsim("animate m", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "2 modes, one cycle of 48 frames each"), r.out);
  const std::string html = pcsim_test::read(w / "m" / "animation.html");
  BOOST_TEST(pcsim_test::has(html, "default-src 'none'"));
  BOOST_TEST(pcsim_test::has(html, "\"modePages\""));
  BOOST_TEST(pcsim_test::has(html, "mode 2 (oscillatory)"));
  BOOST_TEST(pcsim_test::has(html, "natural frequency 5.33862 rad/s"));
  // modes can be rerun into the directory (animation.html and model.toml are pcsim's files)
  r = run_pcsim(modes_cmd, kSource);
  BOOST_TEST(r.status == 0, r.out);

  // In process: every frame of mode 2 is the drawing at q_ref + a Re(v e^{i phi}) (the masses
  // are drawn at (x1, y1), (x2, y2)), a chosen to make the largest displacement 15% of the
  // drawing's 1.7 m height (the masses hang at y = -1 and -1.7 below the pivot).
  r = run_pcsim("animate m", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  {
    std::ifstream in(w / "m" / "modes.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    const pcsim::animate::Scene s = pcsim::animate::read_modes_scene(w / "m", 2000);
    BOOST_TEST_REQUIRE(s.mode_pages.size() == 2u);
    const auto& pg = s.mode_pages[1];
    double vmax = 0;
    for (const char* c : {"x1", "y1", "x2", "y2"}) vmax = std::max(vmax, j["modes"][1]["shape"][c]["abs"].get<double>());
    BOOST_TEST(std::abs(pg.amplitude * vmax - 0.15 * 1.7) <= 1e-9);
    std::size_t m1 = 0, m2 = 0;
    for (std::size_t i = 0; i < s.spec.points.size(); ++i) {
      if (s.spec.points[i].name == "m1") m1 = i;
      if (s.spec.points[i].name == "m2") m2 = i;
    }
    for (std::size_t f = pg.first; f < pg.first + pg.count; ++f) {
      const double phi = s.t[f];
      auto expect = [&](const char* c) {
        const auto& v = j["modes"][1]["shape"][c];
        return j["reference"]["q"][c].get<double>() +
               pg.amplitude * (v["re"].get<double>() * std::cos(phi) - v["im"].get<double>() * std::sin(phi));
      };
      BOOST_TEST(std::abs(s.values[f][3 * m1] - expect("x1")) <= 1e-12);
      BOOST_TEST(std::abs(s.values[f][3 * m1 + 1] - expect("y1")) <= 1e-12);
      BOOST_TEST(std::abs(s.values[f][3 * m2] - expect("x2")) <= 1e-12);
      BOOST_TEST(std::abs(s.values[f][3 * m2 + 1] - expect("y2")) <= 1e-12);
    }
  }

  auto before = listing(w / "m");
  r = run_pcsim("animate m --video m.mp4", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "--video"), r.out);
  BOOST_TEST(listing(w / "m") == before);
  BOOST_TEST(!fs::exists(w / "m.mp4"));

  // no model.toml (a modes directory written before it was written)
  fs::copy(w / "m", w / "old", fs::copy_options::recursive);
  fs::remove(w / "old" / "model.toml");
  fs::remove(w / "old" / "animation.html");
  before = listing(w / "old");
  r = run_pcsim("animate old", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "no model.toml"), r.out);
  BOOST_TEST(listing(w / "old") == before);

  // a torn modes.json
  fs::copy(w / "m", w / "torn", fs::copy_options::recursive);
  fs::remove(w / "torn" / "animation.html");
  std::string mj = pcsim_test::read(w / "torn" / "modes.json");
  mj.resize(mj.size() / 2);
  std::ofstream(w / "torn" / "modes.json") << mj;
  before = listing(w / "torn");
  r = run_pcsim("animate torn", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "modes.json"), r.out);
  BOOST_TEST(listing(w / "torn") == before);

  // a --vary trace has no modes.json
  r = run_pcsim("modes '" + (kSource / "cases/double_pendulum.toml").string() + "' --out '" + (w / "vary").string() +
                    "'" + at_rest + " --vary parameters.L2=0.5:0.9:3", kSource);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  before = listing(w / "vary");
  r = run_pcsim("animate vary", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "no modes.json"), r.out);
  BOOST_TEST(listing(w / "vary") == before);

  // a model with nothing to draw
  std::ofstream(w / "spring.toml") << "[model]\nname = \"spring\"\ncoordinates = [\"x\"]\n[model.parameters]\nk = 1.0\n"
                                      "[model.energy]\nkinetic = \"0.5*x_d^2\"\npotential = \"0.5*k*x^2\"\n";
  std::ofstream(w / "spring_case.toml") << "model = \"spring.toml\"\n[initial]\nx = 0\n";
  r = run_pcsim("modes spring_case.toml --out spring_modes", w);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  before = listing(w / "spring_modes");
  r = run_pcsim("animate spring_modes", w);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(pcsim_test::has(r.out, "nothing to draw"), r.out);
  BOOST_TEST(pcsim_test::has(r.out, "spring.toml"), r.out);
  BOOST_TEST(listing(w / "spring_modes") == before);
}
