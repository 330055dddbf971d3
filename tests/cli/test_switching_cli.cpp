// The switching simulation from the shell: `pcsim run` with contact.switching writes events.csv
// and a mode column per unilateral constraint and reports the hops in words; a run that needs an
// LCP fails with exit 3 and names the library when the plugin cannot be loaded, while a run that
// needs none does not care; bad combinations are refused with exit 2 before any computation.
#define BOOST_TEST_MODULE switching_cli
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "switching_cli.hpp"

using namespace switching_cli;

// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(run_writes_events_and_mode_columns_and_reports_the_hops, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  TempDir dir("switching_cli");
  const fs::path out = dir.path / "hop";
  const Result r = pcsim("run cases/sieve_1995_hopping.toml --set solver.t_end=0.5 --out '" + out.string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  BOOST_TEST(r.out.find("once per period") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("events.csv") != std::string::npos);
  const std::string events = read(out / "events.csv");
  BOOST_TEST(events.rfind("t,kind,constraint,mode_before,mode_after,normal,tangential,vn_before,vn_after,"
                          "vt_before,vt_after,energy_lost\n", 0) == 0);
  BOOST_TEST(events.find(",lift_off,contact,") != std::string::npos);
  BOOST_TEST(events.find(",impact,contact,") != std::string::npos);
  std::istringstream ts(read(out / "timeseries.csv"));
  std::string header, line;
  std::getline(ts, header);
  BOOST_TEST(header.size() > 13u);
  BOOST_TEST(header.substr(header.size() - 13) == ",mode_contact");
  std::set<std::string> modes;
  while (std::getline(ts, line)) modes.insert(line.substr(line.rfind(',') + 1));
  BOOST_TEST(modes.count("flight") == 1u);
  BOOST_TEST(modes.count("stick") == 1u);
  for (const auto& m : modes) BOOST_TEST((m == "flight" || m == "stick" || m == "slip"), m);
  // Without switching the same case has no events.csv and no mode column.
  const fs::path plain = dir.path / "plain";
  const Result p = pcsim("run cases/sieve_1995.toml --set solver.t_end=0.2 --out '" + plain.string() + "'");
  BOOST_REQUIRE_MESSAGE(p.status == 0, p.out);
  BOOST_TEST(!fs::exists(plain / "events.csv"));
  BOOST_TEST(read(plain / "timeseries.csv").find("mode_") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(a_missing_lcp_library_is_named_only_when_an_lcp_is_needed) {
  TempDir dir("switching_cli");
  const std::string env = "PCSIM_LCP_LIBRARY=/nonexistent/pcsim_lcp_siconos.so";
  const Result r = pcsim("run cases/rocking_block.toml --out '" + (dir.path / "rb").string() + "'", env);
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(r.out.find("pcsim_lcp_siconos.so") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("libsiconos-numerics") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("t = 0.19") != std::string::npos, r.out);  // the first impact's time
  // One contact never needs the LCP: the same environment does not matter.
  const Result b = pcsim("run cases/bouncing_ball.toml --out '" + (dir.path / "bb").string() + "'", env);
  BOOST_TEST(b.status == 0, b.out);
}

// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(impossible_combinations_are_refused_before_computing, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  struct Bad {
    std::string args, key;
  };
  const std::vector<Bad> bad = {
      {"run cases/sieve_1995_hopping.toml --set solver.form=dae", "solver.form"},
      {"run cases/sieve_1995_hopping.toml --set constraints.contact=false", "contact.switching"},
      {"run cases/sieve_1995_hopping.toml --set constraints.rolling_as_printed=true", "constraints.rolling_as_printed"},
      {"run cases/sieve_1995_hopping.toml --set contact.zeno_time=0", "contact.zeno_time"},
      {"run cases/sieve_1995_hopping.toml --set contact.lcp_solver=pgs", "contact.lcp_solver"},
      {"run cases/sieve_1995_hopping.toml --set parameters.e_n=1.5", "parameters.e_n"},
  };
  TempDir dir("switching_cli");
  for (const auto& b : bad) {
    const fs::path out = dir.path / "x";
    const Result r = pcsim(b.args + " --out '" + out.string() + "'");
    BOOST_TEST_CONTEXT(b.args) {
      BOOST_TEST(r.status == 2, r.out);
      BOOST_TEST(r.out.find("key '" + b.key + "'") != std::string::npos, r.out);
      BOOST_TEST(!fs::exists(out / "summary.json"));
    }
  }
  // A model without unilateral constraints.
  const fs::path cf = dir.path / "pendulum.toml";
  std::ofstream(cf) << "model = \"pendulum\"\n[initial]\nx = 1.0\n[contact]\nswitching = true\n";
  const Result r = pcsim("run '" + cf.string() + "' --out '" + (dir.path / "p").string() + "'");
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(r.out.find("key 'contact.switching'") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("declares none") != std::string::npos, r.out);
}

namespace {
void write_file(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}
// A column of a timeseries.csv, by name.
std::vector<double> column(const std::string& csv, const std::string& name) {
  std::istringstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::istringstream h(header);
  std::string cell;
  int k = 0, want = -1;
  while (std::getline(h, cell, ',')) {
    if (cell == name) want = k;
    ++k;
  }
  BOOST_REQUIRE(want >= 0);
  std::vector<double> v;
  while (std::getline(in, row)) {
    std::istringstream rs(row);
    for (int i = 0; i <= want; ++i) std::getline(rs, cell, ',');
    v.push_back(std::stod(cell));
  }
  return v;
}
// The rows of an events.csv, its header left out.
std::vector<std::string> event_rows(const fs::path& events) {
  std::istringstream in(read(events));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  return rows;
}
std::string ball_case(const std::string& model, const std::string& initial, double t_end) {
  return "model = \"" + std::string(PCSIM_SOURCE_DIR) + "/tests/mech/contacts/models/" + model +
         ".toml\"\n[parameters]\ne_n = 0.8\n[initial]\n" + initial +
         "\n[contact]\nswitching = true\nzeno_time = 1e-9\n[solver]\nmethod = \"auto\"\nrtol = 1e-10\n"
         "atol = 1e-10\nt_end = " + std::to_string(t_end) + "\n[output]\ndt = 1e-3\nsummary_time = " +
         std::to_string(t_end) + "\n";
}
}  // namespace

// Issue 19: the report and summary say where a contact went inside its surface, count that in
// "max constraint residual", and take "in flight" from the flights recorded.
BOOST_AUTO_TEST_CASE(report_states_penetration_residual_and_flight_time) {
  TempDir dir("switching_cli");
  // The ball, 50 m along the floor: rests at t = 4.0637 s after 93 impacts.
  write_file(dir.path / "far.toml", ball_case("ball_far_along_floor", "x = 50.0\ny = 1.0", 6.0));
  const Result r = pcsim("run '" + (dir.path / "far.toml").string() + "' --out '" + (dir.path / "far").string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  BOOST_TEST(r.out.find("93 impacts") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("in flight 67.7 % of the time") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("deepest penetration") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("WARNING") == std::string::npos, r.out);
  const auto s = nlohmann::json::parse(read(dir.path / "far" / "summary.json"));
  const auto& floor = s["switching"]["contacts"]["floor"];
  BOOST_TEST(floor["run"]["penetration_max"].get<double>() < 1e-12);
  BOOST_TEST(floor["inside_at_end"].get<bool>() == false);
  BOOST_TEST(s["constraint_residual_max"].get<double>() >= floor["run"]["penetration_max"].get<double>());
  // In flight: the recorded flights, and the time-series rows whose mode is flight, agree.
  const double ff = floor["window"]["flight_fraction"].get<double>();
  BOOST_TEST(std::abs(ff + floor["window"]["contact_fraction"].get<double>() - 1.0) < 1e-9);
  std::istringstream ts(read(dir.path / "far" / "timeseries.csv"));
  std::string line;
  std::getline(ts, line);
  long rows = 0, flying = 0;
  while (std::getline(ts, line)) {
    ++rows;
    flying += line.substr(line.rfind(',') + 1) == "flight";
  }
  BOOST_TEST(std::abs(static_cast<double>(flying) / rows - ff) < 2.0 / rows, flying << " of " << rows << " rows, " << ff);

  // A ball that starts 0.5 m inside the floor and is still inside at the end: said plainly.
  write_file(dir.path / "inside.toml", ball_case("ball_far_along_floor", "x = 0.0\ny = -0.5\ny_d = 0.1", 0.01));
  const Result in = pcsim("run '" + (dir.path / "inside.toml").string() + "' --out '" + (dir.path / "inside").string() + "'");
  BOOST_REQUIRE_MESSAGE(in.status == 0, in.out);
  BOOST_TEST(in.out.find("deepest penetration 0.5 m (t = 0 s)") != std::string::npos, in.out);
  BOOST_TEST(in.out.find("WARNING: ends 0.499") != std::string::npos, in.out);
  BOOST_TEST(in.out.find("max constraint residual 0.5") != std::string::npos, in.out);
  const auto si = nlohmann::json::parse(read(dir.path / "inside" / "summary.json"));
  BOOST_TEST(si["switching"]["contacts"]["floor"]["inside_at_end"].get<bool>());
  BOOST_TEST(si["switching"]["penetration_max"].get<double>() == 0.5);

  // The rocking block with e_n = 1 and friction: the impacts where Newton's law would have
  // created energy are counted and named.
  const Result rb = pcsim("run cases/rocking_block.toml --set parameters.e_n=1 --set solver.t_end=5 --out '" +
                          (dir.path / "rb").string() + "'");
  BOOST_REQUIRE_MESSAGE(rb.status == 0, rb.out);
  BOOST_TEST(rb.out.find("impacts where Newton's restitution would have created kinetic energy") != std::string::npos, rb.out);
  const auto sr = nlohmann::json::parse(read(dir.path / "rb" / "summary.json"));
  BOOST_TEST(sr["switching"]["energy_limited_impacts"].get<long>() > 0);
  BOOST_TEST(sr["switching"]["energy_dissipated"]["impacts"].get<double>() >= 0.0);
}

// Counts in messages are in the right number (issue 19: "more than 1 steps"): the event budget
// of 1 is "1 event", a budget of 2 "2 events".
BOOST_AUTO_TEST_CASE(event_budget_message_counts_in_the_right_number) {
  const TempDir dir("sw_cli_counted");
  const Result one = pcsim("run cases/bouncing_ball.toml --set contact.max_events=1 --out '" +
                           (dir.path / "one").string() + "'");
  BOOST_TEST(one.status == 3);
  BOOST_TEST_INFO(one.out);
  BOOST_TEST(one.out.find("2 events, more than contact.max_events = 1 event;") != std::string::npos);
  BOOST_TEST(one.out.find("1 events") == std::string::npos);
  const Result two = pcsim("run cases/bouncing_ball.toml --set contact.max_events=2 --out '" +
                           (dir.path / "two").string() + "'");
  BOOST_TEST(two.status == 3);
  BOOST_TEST_INFO(two.out);
  BOOST_TEST(two.out.find("3 events, more than contact.max_events = 2 events;") != std::string::npos);
}

// Issue 22 (WHL): the coin on the vibrating plane (a frictionless spatial `wheel`, unilateral)
// from the shell: it lifts off at sin(omega t) = g / (A omega^2) and lands at the closed-form
// instant (models/contact/coin_bodies.toml; the numbers are the tests' in
// tests/mech/contacts/test_switching_vibrating_table.cpp), and so does the coin that rolls while
// it touches (its no-slip rows rough rows). The friction keys that do not apply to a wheel
// (friction on the frictionless disk, friction without unilateral, mu_kinetic above mu_static)
// are refused with exit 2, naming the model file and the key, nothing written; a rolling
// unilateral wheel takes mu_static (its no-slip rows the contact's two Coulomb rows).
BOOST_AUTO_TEST_CASE(coin_on_a_wheel_joint_hops_and_wheel_contact_keys_that_do_not_apply_exit_2) {
  TempDir dir("switching_cli");
  const fs::path out = dir.path / "coin";
  const Result r = pcsim("run cases/coin_vibrating_plane.toml --set solver.t_end=0.06 --out '" + out.string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  std::istringstream ev(read(out / "events.csv"));
  std::string line;
  std::getline(ev, line);
  std::vector<std::pair<std::string, double>> events;
  while (std::getline(ev, line)) {
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1);
    events.emplace_back(line.substr(c1 + 1, c2 - c1 - 1), std::stod(line.substr(0, c1)));
  }
  BOOST_REQUIRE(events.size() >= 2u);
  BOOST_TEST(events[0].first == "lift_off");
  BOOST_TEST(std::abs(events[0].second - std::asin(9.81 / (0.002 * 100.0 * 100.0)) / 100.0) < 1e-9);
  BOOST_TEST(events[1].first == "impact");
  BOOST_TEST(std::abs(events[1].second - 0.0523657781873) < 1e-9);
  // The coin rolling (cases/coin_rolling_vibrating_plane.toml: its wheel's no-slip rows are
  // rough rows, released in flight) lifts off and lands at the same instants.
  const fs::path rolling = dir.path / "rolling";
  const Result rr = pcsim("run cases/coin_rolling_vibrating_plane.toml --set solver.t_end=0.06 --out '" +
                          rolling.string() + "'");
  BOOST_REQUIRE_MESSAGE(rr.status == 0, rr.out);
  const std::string rolled = read(rolling / "events.csv");
  BOOST_TEST(rolled.find(",lift_off,bounce_n,contact,flight,") != std::string::npos, rolled);
  BOOST_TEST(rolled.find(",impact,bounce_n,flight,contact,") != std::string::npos, rolled);
  const double t_lift = std::stod(rolled.substr(rolled.find('\n') + 1));
  BOOST_TEST(std::abs(t_lift - events[0].second) < 1e-9, rolled);
  // The joint's contact keys, from `no_slip = false` to `restitution = "e_n"`, replaced.
  std::string model = read(fs::path(PCSIM_SOURCE_DIR) / "models/contact/coin_bodies.toml");
  const std::string first = "\nno_slip = false", last = "\nrestitution = \"e_n\"";
  const auto from = model.find(first), to = model.find(last, from);
  BOOST_REQUIRE(from != std::string::npos);
  BOOST_REQUIRE(to != std::string::npos);
  auto with_keys = [&](const std::string& keys) {
    std::string text = model;
    text.replace(from, to + last.size() - from, keys);
    return text;
  };
  struct Bad {
    std::string keys, key, why;
  };
  for (const Bad& b : {Bad{"\nno_slip = false\nunilateral = true\nmu_static = 0.3", "model.joint.bounce.mu_static",
                           "a frictionless disk (its one row bounce_n is the contact); drop no_slip = false to get "
                           "Coulomb friction on its rows bounce_x, bounce_y"},
                       Bad{"\nmu_static = 0.3", "model.joint.bounce.mu_static", "only with unilateral = true"},
                       Bad{"\nunilateral = true\nmu_static = 0.3\nmu_kinetic = 0.5", "model.joint.bounce.mu_kinetic",
                           "a kinetic friction coefficient in [0, mu_static = 0.3], got 0.5"}}) {
    BOOST_TEST_CONTEXT(b.key) {
      const std::string text = with_keys(b.keys);
      const fs::path mf = dir.path / "coin_bad.toml", cf = dir.path / "coin_bad_case.toml", o = dir.path / "bad";
      write_file(mf, text);
      write_file(cf, "model = \"coin_bad.toml\"\n[initial]\ncoin_e0 = 1\ncoin_z = 0.1\n[contact]\nswitching = true\n");
      const Result e = pcsim("run '" + cf.string() + "' --out '" + o.string() + "'");
      BOOST_TEST(e.status == 2, e.out);
      BOOST_TEST(e.out.find("coin_bad.toml: key '" + b.key + "'") != std::string::npos, e.out);
      BOOST_TEST(e.out.find(b.why) != std::string::npos, e.out);
      BOOST_TEST(!fs::exists(o));
    }
  }
  // The rolling unilateral coin with friction: `pcsim expand` prints its rows bounce_x, bounce_y
  // as the contact's Coulomb rows.
  const fs::path mf = dir.path / "coin_mu.toml";
  write_file(mf, with_keys("\nunilateral = true\nrestitution = \"e_n\"\nmu_static = 0.3\nmu_kinetic = 0.2"));
  const Result x = pcsim("expand '" + mf.string() + "'");
  BOOST_TEST(x.status == 0, x.out);
  for (const char* row : {"bounce_x", "bounce_y"}) {
    const auto at = x.out.find(std::string("name = \"") + row + "\"");
    BOOST_TEST_REQUIRE(at != std::string::npos, x.out);
    const std::string block = x.out.substr(at, x.out.find("\n\n", at) - at);
    BOOST_TEST(block.find("\nfriction = \"bounce_n\"\nmu_static = \"0.3\"\nmu_kinetic = \"0.2\"") != std::string::npos, block);
  }
}

// The coin with friction (cases/coin_skid.toml: a rolling wheel with mu_static, whose no-slip
// rows are the contact's 2-D Coulomb cone) set down skidding rolls from the closed-form instant
// vs/(3 mu_k g): one stick event in events.csv (1e-9 s, the file's digits), its friction work in
// summary.json equal to the kinetic energy lost (1e-9 relative).
BOOST_AUTO_TEST_CASE(a_skidding_coin_case_rolls_from_the_closed_form_instant) {
  TempDir dir("switching_cli");
  const fs::path out = dir.path / "skid";
  const Result r = pcsim("run cases/coin_skid.toml --out '" + out.string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  // The case's numbers as the run read them: the parameters from summary.json, the initial
  // velocity and spin from the time series' first row (the spin about ground y from the Euler
  // parameters, omega = 2 (e0 e_d - e0_d e + e x e_d)), so the test follows an edited case.
  const auto s = nlohmann::json::parse(read(out / "summary.json"));
  const auto& par = s["parameters"];
  const double m = par["m"].get<double>(), rr = par["r"].get<double>(), g = par["g"].get<double>(),
               mu_k = par["mu_k"].get<double>();
  const std::string series = read(out / "timeseries.csv");
  auto first = [&](const char* name) { return column(series, name).front(); };
  auto last = [&](const char* name) { return column(series, name).back(); };
  const double e0 = first("coin_e0"), e1 = first("coin_e1"), e2 = first("coin_e2"), e3 = first("coin_e3"),
               e0d = first("coin_e0_d"), e1d = first("coin_e1_d"), e2d = first("coin_e2_d"), e3d = first("coin_e3_d");
  const double v0 = first("coin_x_d");
  const double w0 = 2 * (e0 * e2d - e0d * e2 + (e3 * e1d - e1 * e3d));
  BOOST_REQUIRE_MESSAGE(v0 - rr * w0 > 0.0, "the case must start skidding forward: v0 " << v0 << ", r w0 " << rr * w0);
  const std::vector<std::string> rows = event_rows(out / "events.csv");
  BOOST_REQUIRE_EQUAL(rows.size(), 1u);
  BOOST_TEST(rows[0].find(",stick,bounce_n,slip,stick,") != std::string::npos, rows[0]);
  const double ts = (v0 - rr * w0) / (3 * mu_k * g);
  BOOST_TEST(std::abs(std::stod(rows[0]) - ts) < 1e-9, rows[0] << " against " << ts);
  const double J = m * rr * rr / 2, v1 = (2 * v0 + rr * w0) / 3;
  const double dT = 0.5 * m * v0 * v0 + 0.5 * J * w0 * w0 - (0.5 * m * v1 * v1 + 0.5 * J * (v1 / rr) * (v1 / rr));
  const double W = s["switching"]["energy_dissipated"]["friction"].get<double>();
  BOOST_TEST(std::abs(W - dT) < 1e-9 * dT, "friction work " << W << " J, kinetic energy lost " << dT << " J");
  // The joint's force in its frame while it skids is the kinetic friction, against the contact
  // point's sliding (+x): F_x = -mu_k m g, F_z = m g, and its moment about the centre r mu_k m g
  // (the columns of the sliding rows carry the friction law's multipliers); once it rolls it
  // needs no friction.
  const double N = m * g;
  BOOST_TEST(std::abs(first("F_bounce_x") + mu_k * N) < 1e-12, first("F_bounce_x"));
  BOOST_TEST(std::abs(first("F_bounce_y")) < 1e-12, first("F_bounce_y"));
  BOOST_TEST(std::abs(first("F_bounce_z") - N) < 1e-12, first("F_bounce_z"));
  BOOST_TEST(std::abs(first("M_bounce_y") - rr * mu_k * N) < 1e-12, first("M_bounce_y"));
  BOOST_TEST(std::abs(last("F_bounce_x")) < 1e-12, last("F_bounce_x"));
  BOOST_TEST(std::abs(last("F_bounce_z") - N) < 1e-12, last("F_bounce_z"));
}

// A 2-D cone's rows are checked before the run (exit 2, nothing written, the rows named): two
// friction rows of one contact with different coefficients (the cone is isotropic), and a third
// friction row.
BOOST_AUTO_TEST_CASE(cone_rows_with_different_coefficients_or_three_friction_rows_exit_2) {
  TempDir dir("switching_cli");
  const std::string model = read(fs::path(PCSIM_SOURCE_DIR) / "models/contact/particle_plane.toml");
  const std::string slide_y = "name = \"slide_y\"";
  std::string diff = model;
  const auto at = diff.find("mu_static = \"mu_s\"", diff.find(slide_y));
  BOOST_REQUIRE(at != std::string::npos);
  diff.replace(at, std::string("mu_static = \"mu_s\"").size(), "mu_static = \"0.5\"");
  const std::string three = model + "\n[[model.constraint]]\nname = \"slide_z\"\nvelocity = { z = \"1\" }\n"
                                    "friction = \"contact\"\nmu_static = \"mu_s\"\nmu_kinetic = \"mu_k\"\n";
  struct Bad {
    std::string text, why;
  };
  for (const Bad& b : {Bad{diff, "the friction constraints 'slide_x' and 'slide_y' of the unilateral constraint 'contact' "
                                 "have different coefficients (mu_static 0.4 and 0.5"},
                       Bad{three, "has three active friction constraints ('slide_x', 'slide_y' and 'slide_z')"}}) {
    write_file(dir.path / "m.toml", b.text);
    write_file(dir.path / "c.toml", "model = \"m.toml\"\n[initial]\nx = 1\nz = 250\nx_d = 1\n[contact]\nswitching = true\n"
                                    "[solver]\nt_end = 1\n");
    const fs::path o = dir.path / "out";
    const Result r = pcsim("run '" + (dir.path / "c.toml").string() + "' --out '" + o.string() + "'");
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(r.out.find(b.why) != std::string::npos, r.out);
    BOOST_TEST(!fs::exists(o));
  }
}


// Issue 22: a solid ball (m = 0.5 kg, r = 0.1 m, J = 2/5 m r^2) rolling without slip off the top
// of a fixed sphere (Rs = 1 m, centred at (300, -200, 80) m; the `ball` joint with surface =
// "sphere", unilateral = true: its no-slip rows rough rows, held while it touches), pushed at
// v0 = 0.05 m/s from the top. With th the angle of the centre from the top, L = Rs + r and v the
// centre's speed (the spin v/r, no slip), energy: (m + J/r^2)(v^2 - v0^2) = 2 m g L (1 - cos th),
// so v^2 = v0^2 + (10/7) g L (1 - cos th); radially, m g cos th - N = m v^2/L, and it lifts off where
// N = 0: g L cos th = v^2, i.e. cos th = (7 v0^2/(g L) + 10)/17 (10/17 from rest at the top).
// The run (switching, rtol 1e-10) reports one lift-off; run again to the event's instant, the
// centre's height there gives cos th, which matches to 1e-8 (measured 1.3e-10: the event's
// location, ~1e-10 s at the centre's 1.9 m/s); T + V stays constant over the run, rolling and in
// flight, to 1e-7 J of the 1.6 J kinetic energy at lift-off (measured 2.7e-9 J).
BOOST_AUTO_TEST_CASE(ball_rolling_off_a_sphere_lifts_off_at_cos_ten_seventeenths) {
  TempDir dir("switching_cli");
  std::string model = read(fs::path(PCSIM_SOURCE_DIR) / "models/ball_bowl_bodies.toml");
  const auto at = model.find("\ninside = true");  // the joint's key, not the header's words
  BOOST_REQUIRE(at != std::string::npos);
  model.replace(at, 14, "\nunilateral = true");
  std::ofstream(dir.path / "m.toml") << model;
  std::ofstream(dir.path / "c.toml") << "model = \"m.toml\"\n[initial]\nball_x = 300.0\nball_y = -200.0\n"
                                        "ball_z = 81.1\nball_e0 = 1.0\nball_x_d = 0.05\nball_wy = 0.5\n"
                                        "[contact]\nswitching = true\n[solver]\nrtol = 1.0e-10\natol = 1.0e-12\n"
                                        "t_end = 3.0\n[output]\ndt = 1.0e-3\n";
  const fs::path out = dir.path / "off";
  const Result r = pcsim("run '" + (dir.path / "c.toml").string() + "' --out '" + out.string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  const std::vector<std::string> lines = event_rows(out / "events.csv");
  BOOST_REQUIRE_EQUAL(lines.size(), 1u);
  BOOST_TEST(lines[0].find(",lift_off,roll_n,contact,flight,") != std::string::npos, lines[0]);
  const std::string t_lift = lines[0].substr(0, lines[0].find(','));
  const std::vector<double> energy = column(read(out / "timeseries.csv"), "energy");
  const auto [lo, hi] = std::minmax_element(energy.begin(), energy.end());
  const fs::path to = dir.path / "to_lift";
  const Result r2 = pcsim("run '" + (dir.path / "c.toml").string() + "' --set solver.t_end=" + t_lift + " --out '" +
                          to.string() + "'");
  BOOST_REQUIRE_MESSAGE(r2.status == 0, r2.out);
  const double z = column(read(to / "timeseries.csv"), "ball_z").back();
  const double L = 1.1, g = 9.81, v0 = 0.05, expected = (7 * v0 * v0 / (g * L) + 10) / 17;
  BOOST_TEST_MESSAGE("ball off a sphere: lifts off at t = " << t_lift << " s, cos th " << (z - 80.0) / L << " vs "
                     << expected << " (difference " << (z - 80.0) / L - expected << ")" << "; energy range " << *hi - *lo << " J");
  BOOST_TEST(std::abs((z - 80.0) / L - expected) < 1e-8);
  BOOST_TEST(*hi - *lo < 1e-7);
}

// Issue 22: a disk dropped into a spinning ring (cases/disk_ring_bodies.toml: a rolling joint on
// the ring's circle, inside) slides, sticks once (at 0.084 s) and then rolls: over the summary
// window after the stick its `slip` output, the rolling relation (R - r) psi_d + r th_d - R Omega,
// stays 0 (1e-8 m/s) and its gap closed (1e-8 m). A ring the disk does not fit in, or a holonomic
// rolling row on a circle, exits 2 naming the model file and the key, nothing written.
BOOST_AUTO_TEST_CASE(a_disk_in_a_spinning_ring_sticks_once_and_bad_circle_keys_exit_2) {
  TempDir dir("switching_cli");
  const fs::path out = dir.path / "ring";
  const Result r = pcsim("run cases/disk_ring_bodies.toml --set solver.t_end=0.5 --set output.summary_time=0.4 --out '" +
                         out.string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  const std::vector<std::string> lines = event_rows(out / "events.csv");
  BOOST_REQUIRE_EQUAL(lines.size(), 1u);
  BOOST_TEST(lines[0].find(",stick,mill_contact,slip,stick,") != std::string::npos, lines[0]);
  const double t_stick = std::stod(lines[0]);
  BOOST_TEST((t_stick > 0.08 && t_stick < 0.09), t_stick);
  const auto summary = nlohmann::json::parse(read(out / "summary.json"));
  for (const char* c : {"slip", "gap"})
    for (const char* e : {"min", "max"}) BOOST_TEST(std::abs(summary["extremes"][c][e].get<double>()) < 1e-8, c << " " << e);
  const std::string model = read(fs::path(PCSIM_SOURCE_DIR) / "models/contact/disk_ring_bodies.toml");
  struct Bad {
    std::string from, to, key, why;
  };
  for (const Bad& b : {Bad{"circle_radius = \"R\"", "circle_radius = \"r\"", "model.joint.mill.circle_radius",
                           "a radius > the wheel's radius = 0.1 with inside = true (the wheel rolls inside the circle), got r = 0.1"},
                       Bad{"inside = true", "inside = true\nform = \"holonomic\"", "model.joint.mill.form", "\"velocity\" on a circle"},
                       Bad{"surface = \"circle\"", "surface = \"cylinder\"", "model.joint.mill.surface",
                           "\"line\" (default: marker1's x axis) or \"circle\" (centred at marker1, radius circle_radius), got 'cylinder'"}}) {
    BOOST_TEST_CONTEXT(b.key) {
      std::string text = model;
      const auto at = text.find("\n" + b.from + "\n");  // the joint's key, not the header's words
      BOOST_REQUIRE(at != std::string::npos);
      text.replace(at + 1, b.from.size(), b.to);
      std::ofstream(dir.path / "m.toml") << text;
      std::ofstream(dir.path / "c.toml") << "model = \"m.toml\"\n[initial]\ndisk_x = 0.0\n[contact]\nswitching = true\n";
      const fs::path o = dir.path / "bad";
      const Result e = pcsim("run '" + (dir.path / "c.toml").string() + "' --out '" + o.string() + "'");
      BOOST_TEST(e.status == 2, e.out);
      BOOST_TEST(e.out.find("m.toml: key '" + b.key + "': " + b.why) != std::string::npos, e.out);
      BOOST_TEST(!fs::exists(o));
    }
  }
}

// The ball skidding in the bowl (models/ball_bowl_bodies.toml with unilateral = true and a 2-D
// cone, mu = 0.05): launched at the bottom at (3.6, 0.5) m/s without spin, it slides up the side.
// Run twice: with marker1 as in the file (z up: the tangents' first chart, w1·n from 1 to 0.4 on
// this path) and turned upside down (axis x, angle pi: it starts at n = −w1, where the first chart
// alone divided by zero, in the second chart, and crosses the chart switch w1·n = −1/2 near
// t = 0.33 s while sliding). The frames only change the tangents the cone's rows are taken along,
// so the two runs are the same motion: every sample of the centre's position and velocity agrees
// to 1e-7 (m, m/s; both runs at rtol 1e-10, measured 2e-8 at rtol 1e-9), and neither has an event
// before t = 0.4 s (the chart switch fires no stop of the sliding).
BOOST_AUTO_TEST_CASE(a_ball_skidding_in_a_bowl_through_the_tangent_chart_switch_moves_as_with_one_chart) {
  TempDir dir("switching_cli");
  std::string model = read(fs::path(PCSIM_SOURCE_DIR) / "models/ball_bowl_bodies.toml");
  const auto at = model.find("\ninside = true");
  BOOST_REQUIRE(at != std::string::npos);
  model.replace(at, 14, "\ninside = true\nunilateral = true\nmu_static = 0.05\nmu_kinetic = 0.05");
  model.replace(model.find("[model.outputs]"), 15, "[model.outputs]\ncw = \"roll_cw\"");
  const std::string plain = "centre = [\"X0\", \"Y0\", \"Z0\"]";
  std::string flipped = model;
  BOOST_REQUIRE(flipped.find(plain) != std::string::npos);
  flipped.replace(flipped.find(plain), plain.size(), "centre = { at = [\"X0\", \"Y0\", \"Z0\"], axis = [1, 0, 0], angle = \"pi\" }");
  std::map<std::string, std::string> text{{"upright", model}, {"flipped", flipped}};
  for (const auto& [name, m] : text) {
    std::ofstream(dir.path / (name + ".toml")) << m;
    std::ofstream(dir.path / (name + "_case.toml"))
        << "model = \"" << name << ".toml\"\n[initial]\nball_x = 300.0\nball_y = -200.0\nball_z = 79.1\nball_e0 = 1.0\n"
        << "ball_x_d = 3.6\nball_y_d = 0.5\n[contact]\nswitching = true\n[solver]\nrtol = 1.0e-10\natol = 1.0e-12\n"
        << "t_end = 0.4\n[output]\ndt = 1.0e-3\n";
    const Result r = pcsim("run '" + (dir.path / (name + "_case.toml")).string() + "' --out '" + (dir.path / name).string() + "'");
    BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
    const std::vector<std::string> events = event_rows(dir.path / name / "events.csv");
    BOOST_TEST(events.empty(), name << ": an event " << (events.empty() ? "" : events[0]));
  }
  const std::string up = read(dir.path / "upright" / "timeseries.csv"), fl = read(dir.path / "flipped" / "timeseries.csv");
  const std::vector<double> cw_up = column(up, "cw"), cw_fl = column(fl, "cw");
  BOOST_TEST(cw_fl.front() == -1.0);  // the start is the first chart's singular point
  BOOST_TEST(*std::min_element(cw_up.begin(), cw_up.end()) > -0.5);
  BOOST_TEST(*std::max_element(cw_fl.begin(), cw_fl.end()) > -0.5);  // the flipped run switches
  double worst = 0;
  for (const char* c : {"ball_x", "ball_y", "ball_z", "ball_x_d", "ball_y_d", "ball_z_d"}) {
    const std::vector<double> a = column(up, c), b = column(fl, c);
    BOOST_REQUIRE_EQUAL(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  }
  BOOST_TEST_MESSAGE("ball skidding through the chart switch: the two frames' runs differ by " << worst << " at most");
  BOOST_TEST(worst < 1e-7);
}
