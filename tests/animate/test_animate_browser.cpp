// pcsim animate's page in a real browser (Debian's chromium, headless, offline): set to a time
// by its URL fragment, it draws the named points where the time series puts them (oracles
// written here from the models' geometry, not the page's code), to the drawing's resolution;
// it shows the contact modes of the run; and it makes no network request (chromium's net log,
// checked against a control page that does make requests).
#define BOOST_TEST_MODULE animate_browser
#include <boost/test/unit_test.hpp>

#include <fstream>

#include "animate_util.hpp"

using namespace animate_test;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = PCSIM_SOURCE_DIR;

struct Run {
  pcsim_test::TempDir scratch;
  fs::path out;
  Series series;
  Run(const std::string& tag, const std::string& case_file, const std::string& sets)
      : scratch("animate_" + tag), out(scratch.path / "out") {
    const Result r = run_pcsim("run '" + (kSource / case_file).string() + "' --out '" + out.string() + "' " + sets, kSource);
    BOOST_TEST_REQUIRE(r.status == 0, r.out);
    const Result a = run_pcsim("animate '" + out.string() + "'", kSource);
    BOOST_TEST_REQUIRE(a.status == 0, a.out);
    series = read_series(out / "timeseries.csv");
  }
  fs::path page() const { return out / "animation.html"; }
};

// One pixel of the drawing in world units: the page's resolution.
double pixel(const nlohmann::json& s) { return 1.0 / s.at("pixels_per_unit").get<double>(); }

}  // namespace

BOOST_AUTO_TEST_CASE(the_pendulum_bob_is_drawn_where_the_time_series_puts_it_and_nothing_is_fetched) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()), "Debian's chromium is needed (scripts/install-deps.sh)");
  Run run("pendulum", "cases/double_pendulum.toml", "--set solver.t_end=1.5");
  const fs::path netlog = run.scratch.path / "net.json";
  const nlohmann::json s = page_state(run.page(), "t=1.25&mag=1", run.scratch.path, netlog);
  BOOST_TEST_REQUIRE(s.is_object(), "the page wrote no state");
  const double t = s.at("t").get<double>();
  BOOST_TEST(std::abs(t - 1.25) <= 2e-3);  // the frame nearest the time asked for
  const std::size_t row = run.series.row_at(t);
  BOOST_TEST(run.series.col.at("t")[row] == t);
  const double res = pixel(s);
  BOOST_TEST(res < 0.01);  // a 1000-pixel view of a 3 m drawing
  // The masses are (x1, y1) and (x2, y2) of the time series, the pivot the origin.
  BOOST_TEST(std::abs(s["points"]["m1"][0].get<double>() - run.series.col.at("x1")[row]) <= res);
  BOOST_TEST(std::abs(s["points"]["m1"][1].get<double>() - run.series.col.at("y1")[row]) <= res);
  BOOST_TEST(std::abs(s["points"]["m2"][0].get<double>() - run.series.col.at("x2")[row]) <= res);
  BOOST_TEST(std::abs(s["points"]["m2"][1].get<double>() - run.series.col.at("y2")[row]) <= res);
  BOOST_TEST(s["points"]["pivot"][0].get<double>() == 0.0);
  // Pixels: the same scale in x and y, y up: the pixel offset of m2 from the pivot is the
  // world offset times the scale, to half a pixel.
  const double k = s.at("pixels_per_unit").get<double>();
  const auto& px = s["pixels"];
  BOOST_TEST(std::abs((px["m2"][0].get<double>() - px["pivot"][0].get<double>()) - k * run.series.col.at("x2")[row]) <= 0.5);
  BOOST_TEST(std::abs((px["m2"][1].get<double>() - px["pivot"][1].get<double>()) + k * run.series.col.at("y2")[row]) <= 0.5);
  // The arrows carry the time series' tension at that time.
  BOOST_TEST(std::abs(s["forces"]["tension2"].get<double>() - run.series.col.at("tension2")[row]) <=
             1e-5 * std::abs(run.series.col.at("tension2")[row]));
  // No request left the page (the control below proves the log would show one).
  const auto urls = page_requests(netlog);
  BOOST_TEST(urls.empty(), (urls.empty() ? std::string() : urls.front()));
  const std::string html = pcsim_test::read(run.page());
  BOOST_TEST(pcsim_test::has(html, "content=\"default-src 'none'"));
}

BOOST_AUTO_TEST_CASE(the_net_log_check_sees_a_page_that_does_fetch) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()));
  pcsim_test::TempDir scratch("animate_control");
  const fs::path page = scratch.path / "control.html";
  std::ofstream(page) << "<html><body><img src=\"http://127.0.0.1:9/x.png\"></body></html>\n";
  const fs::path netlog = scratch.path / "net.json";
  (void)page_state(page, "", scratch.path, netlog);
  const auto urls = page_requests(netlog);
  BOOST_TEST(urls.size() >= 1u);
  bool seen = false;
  for (const auto& u : urls) seen = seen || pcsim_test::has(u, "127.0.0.1:9");
  BOOST_TEST(seen);
}

// The sieve: the roller centre is the desk point (s, u): H = y + s cos(theta) - u sin(theta),
// V = x + s sin(theta) + u cos(theta) (docs/sieve-model.md: X up is x, Y horizontal is y). At
// magnification 1 it is drawn there; at 2000 the desk centre C is drawn at its mean over one
// excitation period plus 2000 times its displacement from that mean (the mean computed here).
BOOST_AUTO_TEST_CASE(the_sieve_roller_and_the_magnified_desk_are_drawn_where_the_run_says,
                     *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()));
  Run run("sieve", "cases/sieve_1995.toml", "--set solver.t_end=0.5");
  const auto& c = run.series.col;
  {
    const nlohmann::json s = page_state(run.page(), "t=0.3&mag=1", run.scratch.path);
    BOOST_TEST_REQUIRE(s.is_object());
    const std::size_t r = run.series.row_at(s["t"].get<double>());
    const double th = c.at("theta")[r], S = c.at("s")[r], U = c.at("u")[r];
    const double H = c.at("y")[r] + S * std::cos(th) - U * std::sin(th);
    const double V = c.at("x")[r] + S * std::sin(th) + U * std::cos(th);
    // 1e-7 m: the page keeps 8 digits of a point's mean and 6 of its displacement.
    BOOST_TEST(std::abs(s["points"]["roller"][0].get<double>() - H) <= 1e-7);
    BOOST_TEST(std::abs(s["points"]["roller"][1].get<double>() - V) <= 1e-7);
    BOOST_TEST(std::abs(s["forces"]["R_u"].get<double>() - c.at("R_u")[r]) <= 1e-5 * c.at("R_u")[r]);
  }
  {
    const nlohmann::json s = page_state(run.page(), "t=0.3&mag=2000", run.scratch.path);
    BOOST_TEST_REQUIRE(s.is_object());
    BOOST_TEST(s["magnify"].get<double>() == 2000.0);
    const double t = s["t"].get<double>();
    const std::size_t r = run.series.row_at(t);
    const double T = 2 * M_PI / 280.0;  // the excitation period
    double mx = 0, my = 0;
    int n = 0;
    for (std::size_t i = 0; i < c.at("t").size(); ++i)
      if (c.at("t")[i] >= t - T / 2 && c.at("t")[i] <= t + T / 2) mx += c.at("x")[i], my += c.at("y")[i], ++n;
    mx /= n;
    my /= n;
    const double H = my + 2000 * (c.at("y")[r] - my), V = mx + 2000 * (c.at("x")[r] - mx);
    const double res = pixel(s);
    BOOST_TEST(std::abs(s["points"]["C"][0].get<double>() - H) <= res);
    BOOST_TEST(std::abs(s["points"]["C"][1].get<double>() - V) <= res);
    // and it moved: the magnified displacement is many pixels
    BOOST_TEST(std::abs(V - mx) > 5 * res);
  }
}

BOOST_AUTO_TEST_CASE(a_switching_run_shows_the_contact_mode_of_the_time_series) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()));
  Run run("ball", "cases/bouncing_ball.toml", "--set solver.t_end=1.6");
  for (const double t : {0.2, 1.5}) {
    const nlohmann::json s = page_state(run.page(), "t=" + std::to_string(t) + "&mag=1", run.scratch.path);
    BOOST_TEST_REQUIRE(s.is_object());
    const std::size_t r = run.series.row_at(s["t"].get<double>());
    BOOST_TEST(s["modes"]["floor"].get<std::string>() == run.series.text.at("mode_floor")[r]);
    BOOST_TEST(std::abs(s["points"]["bottom"][1].get<double>() - run.series.col.at("y")[r]) <= pixel(s));
  }
}

// A spatial drawing (view = "3d"): the page orbits a camera around it; the bob is drawn at
// (x, y, z) of the time series, and turning the camera moves its pixel but not its position.
BOOST_AUTO_TEST_CASE(a_spatial_drawing_is_drawn_in_3d_where_the_time_series_puts_it) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()));
  Run run("spherical", "tests/animate/spherical_pendulum_case.toml", "");
  const nlohmann::json a = page_state(run.page(), "t=0.7&mag=1&az=0.3", run.scratch.path);
  const nlohmann::json b = page_state(run.page(), "t=0.7&mag=1&az=1.3", run.scratch.path);
  BOOST_TEST_REQUIRE((a.is_object() && b.is_object()));
  const std::size_t r = run.series.row_at(a["t"].get<double>());
  const auto& c = run.series.col;
  BOOST_TEST_REQUIRE(a["points"]["bob"].size() == 3u);
  BOOST_TEST(std::abs(a["points"]["bob"][0].get<double>() - c.at("x")[r]) <= 1e-6);
  BOOST_TEST(std::abs(a["points"]["bob"][1].get<double>() - c.at("y")[r]) <= 1e-6);
  BOOST_TEST(std::abs(a["points"]["bob"][2].get<double>() - c.at("z")[r]) <= 1e-6);
  BOOST_TEST(a["points"]["bob"] == b["points"]["bob"]);
  const double moved = std::hypot(a["pixels"]["bob"][0].get<double>() - b["pixels"]["bob"][0].get<double>(),
                                  a["pixels"]["bob"][1].get<double>() - b["pixels"]["bob"][1].get<double>());
  BOOST_TEST(moved > 10.0);
}

// A `pcsim modes` page (issue 24's modes, drawn by the model's [model.draw]): opened at a mode
// and a phase, the masses of the hanging double pendulum are drawn at q_ref + a Re(v e^{i phi}),
// computed here from modes.json (the reference, the shape) and the page's amplitude and phase.
BOOST_AUTO_TEST_CASE(a_mode_page_draws_the_shape_about_the_reference_at_the_phase_asked_for) {
  BOOST_TEST_REQUIRE(fs::exists(chromium()));
  pcsim_test::TempDir scratch("animate_modes_page");
  const fs::path out = scratch.path / "m";
  Result r = run_pcsim("modes '" + (kSource / "cases/double_pendulum.toml").string() + "' --out '" + out.string() +
                           "' --set initial.x1=0 --set initial.y1=-1 --set initial.x2=0 --set initial.y2=-1.7",
                       kSource);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  r = run_pcsim("animate '" + out.string() + "'", kSource);
  BOOST_TEST_REQUIRE(r.status == 0, r.out);
  std::ifstream in(out / "modes.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const nlohmann::json s = page_state(out / "animation.html", "mode=1&phase=2.0", scratch.path);
  BOOST_TEST_REQUIRE(s.is_object(), "the page wrote no state");
  BOOST_TEST(s.at("mode").get<int>() == 1);
  const double phi = s.at("phase").get<double>(), a = s.at("amplitude").get<double>();
  BOOST_TEST(std::abs(phi - 2.0) <= 3.14159265358979 / 48 + 1e-9);  // the nearest of 48 frames per cycle
  BOOST_TEST(a > 0);
  const double res = pixel(s);
  BOOST_TEST(res < 0.01);  // a 1000-pixel view of a 1.7 m drawing
  const auto& shape = j["modes"][0]["shape"];
  auto expect = [&](const char* c) {
    return j["reference"]["q"][c].get<double>() +
           a * (shape[c]["re"].get<double>() * std::cos(phi) - shape[c]["im"].get<double>() * std::sin(phi));
  };
  BOOST_TEST(std::abs(s["points"]["m1"][0].get<double>() - expect("x1")) <= res);
  BOOST_TEST(std::abs(s["points"]["m1"][1].get<double>() - expect("y1")) <= res);
  BOOST_TEST(std::abs(s["points"]["m2"][0].get<double>() - expect("x2")) <= res);
  BOOST_TEST(std::abs(s["points"]["m2"][1].get<double>() - expect("y2")) <= res);
  // visible: the lower mass (the shape's largest component) moves tens of pixels at cos(phi) = -0.42
  BOOST_TEST(std::abs(s["points"]["m2"][0].get<double>() - j["reference"]["q"]["x2"].get<double>()) / res >= 20);
}
