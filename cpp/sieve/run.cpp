// The sieve client: case keys beyond the generic ones, verdicts over the whole run, the window
// extremes of the paper's signals, the contracted summary keys and the engineer's report.
#include "sieve/run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <limits>
#include <sstream>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "mech/simulation.hpp"
#include "sim/extremes.hpp"
#include "sim/file_source.hpp"
#include "sim/run.hpp"
#include "sim/switching_summary.hpp"

namespace pcsim::sieve {

using sim::RunningMax;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Signals tracked over the summary window, by index.
enum Signal { sig_x, sig_y, sig_theta, sig_Ru, sig_fstar, sig_count };

// Where the sieve's quantities are in a sample, resolved once by name from the model
// (models/sieve_1995.toml): the coordinates x, y, theta, s, u (q, and R of the same index: R_u
// is the reaction on u) and the output fstar.
struct Layout {
  int x = 0, y = 0, theta = 0, s = 0, u = 0, fstar = 0;
};

int index_of(const std::vector<std::string>& names, const char* name) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  throw std::logic_error(std::string("the sieve's model has no '") + name + "'");
}

const Layout& layout() {
  static const Layout l = [] {
    const auto m = sim::embedded_description("sieve_1995");
    Layout r;
    r.x = index_of(m->coordinates(), "x");
    r.y = index_of(m->coordinates(), "y");
    r.theta = index_of(m->coordinates(), "theta");
    r.s = index_of(m->coordinates(), "s");
    r.u = index_of(m->coordinates(), "u");
    std::vector<std::string> outputs;
    for (const auto& o : m->outputs()) outputs.push_back(o.name);
    r.fstar = index_of(outputs, "fstar");
    return r;
  }();
  return l;
}

// What a sieve run's verdicts and summary read, from the typed setup (built once per run).
struct RunSettings {
  Layout at;
  double a = 0, f = 0, m2 = 0, g = 0, e_n = 0;
  sim::ParameterValues parameters;  // for the assumptions
  double s0 = 0, t_end = 0;         // the roller's initial position; the run's end
  bool contact = false, rolling = false, rolling_as_printed = false, lock_theta = false;
  bool switching = false;           // contact.switching (issue 12)
  double w0 = 0, w1 = 0;            // the summary window (sim::summary_window)
};

// A first violation time over the whole run, found on the samples and then located by
// bisection on the dense output of the step where it occurred.
struct Verdict {
  bool active = false;   // the constraint is imposed, so the verdict means something
  double first = kNaN;   // time of the first violation, NaN if none
  bool violated() const { return !std::isnan(first); }
};

class SieveMonitor final : public sim::ClientMonitor {
 public:
  explicit SieveMonitor(RunSettings set) : set_(std::move(set)), at_(set_.at), w0_(set_.w0), w1_(set_.w1) {
    contact_.active = set_.contact;
    rolling_.active = set_.contact && set_.rolling;
  }

  // The stop (the roller left the deck: check) on the integrating thread; the rest, which only
  // reads (observe), behind it (issue 23: sim::ClientMonitor::deferred).
  bool deferred() const override { return true; }

  bool check(const mech::StepView& v) override {
    if (v.t == v.t_prev) return true;  // the consistent initial state
    // The roller's contact point must stay on the deck, xi in [-a, a] (docs/sieve.md): beyond
    // it the model (a roller on an endless plane) no longer describes the machine. Only q is
    // read: the dense output's (v.state), the same values as v.sample's q.
    const double deck = std::abs(set_.a);
    const int is = at_.s;
    auto off_deck = [&](double t) {
      v.state(t, cq_, cqd_);
      return std::abs(cq_(is)) > deck;
    };
    if (off_deck(v.t)) {
      double lo = v.t_prev, hi = v.t;
      for (int it = 0; it < 60 && hi - lo > 1e-13 * std::max(1.0, std::abs(hi)); ++it) {
        const double m = 0.5 * (lo + hi);
        if (off_deck(m)) hi = m; else lo = m;
      }
      stop_t_ = hi;
      stop_reason_ = "the roller left the deck at t = " + format_significant(hi, 9) +
                     " s (|s| > a = " + format_significant(deck, 6) + " m)";
      return false;
    }
    return true;
  }

  // Everything but the stop: the whole run's verdicts, the window's signals.
  bool observe(const mech::StepView& v) override {
    if (v.t == v.t_prev) {  // the consistent initial state
      const mech::Sample s0 = v.at(v.t);
      whole_run(v, s0, s0.t);
      ru_prev_ = ru(s0);
      ru_scale_ = std::abs(ru(s0));
      fstar_prev_ = fstar(s0);
      return true;
    }
    // Whole run: the step's end, and its midpoint too when an end is near a violation (R_u
    // below a quarter of its largest value so far, or f* above 3/4 of f): a smooth signal
    // cannot dip from there to the limit and back within one step (~1/25 of a period) unseen.
    const mech::Sample end = v.at(v.t);
    ru_scale_ = std::max(ru_scale_, std::abs(ru(end)));
    const bool near = (contact_.active && std::min(ru(end), ru_prev_) < 0.25 * ru_scale_) ||
                      (rolling_.active && std::max(fstar(end), fstar_prev_) > 0.75 * set_.f);
    if (near) {
      const double mid = 0.5 * (v.t_prev + v.t);
      whole_run(v, v.at(mid), v.t_prev);
      whole_run(v, end, mid);
    } else {
      whole_run(v, end, v.t_prev);
    }
    ru_prev_ = ru(end);
    fstar_prev_ = fstar(end);
    if (v.t > w0_) window(v);
    return true;
  }

  double stop_time() const override { return stop_t_; }
  std::string stop_reason() const override { return stop_reason_; }

  void finish(const mech::SimulationResult& res, sim::RunResult& result) override {
    nlohmann::json& j = result.additions;
    const double weight = set_.m2 * set_.g;
    const std::string& variant = result.model_variant;
    j["model_form"] = variant.empty() ? std::string("model_file") : variant;
    auto half_pp = [&](int sig) { return 0.5 * (maxima_[sig].value + minima_[sig].value); };
    j["amplitude"] = {{"x", half_pp(sig_x)}, {"y", half_pp(sig_y)}, {"theta", half_pp(sig_theta)}};
    j["theta_mean"] = theta_integral_ / (w1_ - w0_);
    j["theta_max_abs"] = std::max(maxima_[sig_theta].value, minima_[sig_theta].value);
    j["theta_max_abs_run"] =  // step-end samples, and the refined window extremes
        std::max({theta_abs_max_run_, maxima_[sig_theta].value, minima_[sig_theta].value});
    const double ru_min = -minima_[sig_Ru].value, ru_max = maxima_[sig_Ru].value;
    j["R_u_min"] = ru_min;
    j["R_u_max"] = ru_max;
    j["R_u_min_over_weight"] = ru_min / weight;
    const double fstar_max = rolling_.active ? maxima_[sig_fstar].value : kNaN;
    j["fstar_max"] = null_if_nan(fstar_max);
    // A refined window minimum below zero is a violation even if no sample saw it.
    if (contact_.active && !contact_.violated() && !(ru_min > 0)) contact_.first = minima_[sig_Ru].time;
    if (rolling_.active && !rolling_.violated() && !(fstar_max < set_.f))
      rolling_.first = maxima_[sig_fstar].time;
    auto verdict = [](const Verdict& v) {
      return v.active ? nlohmann::json(!v.violated()) : nlohmann::json(nullptr);
    };
    auto when = [](const Verdict& v) { return null_if_nan(v.first); };
    j["contact_kept"] = verdict(contact_);
    j["rolling_kept"] = verdict(rolling_);
    j["first_violation"] = {{"contact", when(contact_)}, {"rolling", when(rolling_)}};
    j["constraint_residual_max"] =
        std::max({residual_max_, res.residual_pos_max, res.residual_vel_max});
    // Margins: (3.1) min R_u/(m2 g) (> 0 kept); (3.2) 1 - max f*/f (> 0 kept).
    const double contact_margin = contact_.active ? ru_min / weight : kNaN;
    const double rolling_margin = rolling_.active ? 1.0 - fstar_max / set_.f : kNaN;
    std::string closer = "n/a";
    // Once R_u <= 0 the friction ratio is undefined (f* = inf): the contact is what failed.
    if (contact_.active && rolling_.active)
      closer = (!(contact_margin > 0) || contact_margin <= rolling_margin) ? "contact (3.1)"
                                                                            : "rolling (3.2)";
    j["margins"] = {{"contact", null_if_nan(contact_margin)},
                    {"rolling", null_if_nan(rolling_margin)},
                    {"closer_to_violation", closer}};
    std::vector<std::string> active;
    if (set_.contact) active.push_back("contact");
    if (set_.rolling) active.push_back("rolling");
    if (set_.lock_theta) active.push_back("lock_theta");
    nlohmann::json as;
    as["note"] =
        "parameters the 1995 paper does not print: the project's documented defaults "
        "(docs/sieve-model.md, section 5) unless the case file sets them";
    for (const char* p : {"g", "x0", "y0", "yc", "b", "yb", "a", "xc", "xb", "u0", "f"})
      as[std::string("parameters.") + p] = set_.parameters.at(p);
    as["initial.s0"] = set_.s0;
    as["solver.t_end"] = set_.t_end;
    as["initial_state"] = "q = (0, 0, 0, s0, u0, 0), q_d = 0 unless [initial] sets them";
    as["constraints"] = active;
    if (set_.switching) as["parameters.e_n"] = set_.e_n;  // the landing's restitution (issue 12)
    j["assumptions"] = as;
    j["rolling_condition"] = set_.rolling_as_printed
                                 ? "s - r phi = const (as printed in (3.2); not physical rolling)"
                                 : "s + r phi = const (erratum 7 of (3.2))";
  }

 private:
  Eigen::VectorXd cq_, cqd_;  // check()'s state (the integrating thread's)

  static nlohmann::json null_if_nan(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  }

  double ru(const mech::Sample& s) const { return s.R(at_.u); }
  double fstar(const mech::Sample& s) const { return s.derived(at_.fstar); }
  double signal(const mech::Sample& s, int which) const {
    switch (which) {
      case sig_x: return s.q(at_.x);
      case sig_y: return s.q(at_.y);
      case sig_theta: return s.q(at_.theta);
      case sig_Ru: return ru(s);
      default: return fstar(s);
    }
  }

  bool contact_violated(const mech::Sample& s) const { return !(ru(s) > 0); }
  bool rolling_violated(const mech::Sample& s) const {
    // With switching, a roller in flight has no contact force at all (f* = 0/0): nothing rolls
    // or slips there; its rolling verdict fails only when it slides (f* = f).
    if (set_.switching && ru(s) == 0.0 && s.R(at_.s) == 0.0) return false;
    return !(fstar(s) < set_.f);
  }

  // Locates the first violation in (a, b] where a is fine and b violates.
  template <class Pred>
  double locate(const mech::StepView& v, double a, double b, Pred violated) const {
    for (int it = 0; it < 60 && b - a > 1e-13 * std::max(1.0, std::abs(b)); ++it) {
      const double m = 0.5 * (a + b);
      if (violated(v.sample(m))) b = m; else a = m;
    }
    return b;
  }

  void whole_run(const mech::StepView& v, const mech::Sample& s, double t_ok) {
    theta_abs_max_run_ = std::max(theta_abs_max_run_, std::abs(s.q(at_.theta)));
    residual_max_ = std::max({residual_max_, s.residual_pos, s.residual_vel});
    auto cv = [this](const mech::Sample& x) { return contact_violated(x); };
    auto rv = [this](const mech::Sample& x) { return rolling_violated(x); };
    if (contact_.active && !contact_.violated() && cv(s))
      contact_.first = (s.t == t_ok) ? s.t : locate(v, t_ok, s.t, cv);
    if (rolling_.active && !rolling_.violated() && rv(s))
      rolling_.first = (s.t == t_ok) ? s.t : locate(v, t_ok, s.t, rv);
  }

  void window(const mech::StepView& v) {
    const double a = std::max(v.t_prev, w0_), b = v.t;
    if (!(b > a)) return;
    constexpr int K = 8;  // 9 samples per step (~27 steps per period) bracket every extremum
    std::vector<double> s(K + 1);
    std::vector<mech::Sample> smp;
    smp.reserve(K + 1);
    for (int k = 0; k <= K; ++k) {
      s[k] = (k == K) ? b : a + (b - a) * k / K;
      smp.push_back(v.at(s[k]));
    }
    std::vector<double> f(K + 1);
    for (int sig = 0; sig < sig_count; ++sig) {
      if (sig == sig_fstar && !rolling_.active) continue;
      for (int k = 0; k <= K; ++k) f[k] = signal(smp[k], sig);
      sim::refine_max(s, f, [&](double x) { return signal(v.sample(x), sig); }, maxima_[sig]);
      if (sig == sig_fstar) continue;  // only the maximum of f* is reported
      for (int k = 0; k <= K; ++k) f[k] = -f[k];
      sim::refine_max(s, f, [&](double x) { return -signal(v.sample(x), sig); }, minima_[sig]);
    }
    // ∫ θ over [a, b] by 3-point Gauss-Legendre: exact for polynomials of degree <= 5, and the
    // dense output of q on one step is a polynomial of degree 3 (the collocation polynomial).
    const double c = 0.5 * (a + b), hw = 0.5 * (b - a), r = std::sqrt(0.6);
    const double th0 = v.sample(c - hw * r).q(at_.theta);
    const double th1 = v.sample(c).q(at_.theta);
    const double th2 = v.sample(c + hw * r).q(at_.theta);
    theta_integral_ += hw * (5.0 / 9.0 * th0 + 8.0 / 9.0 * th1 + 5.0 / 9.0 * th2);
  }

  RunSettings set_;
  Layout at_;
  double w0_, w1_;
  RunningMax maxima_[sig_count], minima_[sig_count];  // minima hold the negated signal
  double theta_integral_ = 0.0;  // ∫ θ dt over the window (Gauss-Legendre per step)
  double theta_abs_max_run_ = 0.0;
  double residual_max_ = 0.0;
  Verdict contact_, rolling_;
  double ru_prev_ = 0, ru_scale_ = 0, fstar_prev_ = 0;  // at the previous step end
  double stop_t_ = 0.0;
  std::string stop_reason_;
};

class SieveClient final : public sim::Client {
 public:
  std::vector<sim::KeySpec> extra_keys() const override {
    sim::KeySpec s0;
    s0.section = "initial";
    s0.name = "s0";
    s0.type = sim::KeySpec::Type::number;
    s0.meaning = "initial roller position, m";
    s0.number_default = 0.40;
    sim::KeySpec printed;
    printed.section = "constraints";
    printed.name = "rolling_as_printed";
    printed.type = sim::KeySpec::Type::boolean;
    printed.meaning =
        "(3.2) with the paper's printed sign s - r phi = const instead of s + r phi = const "
        "(erratum 7)";
    printed.bool_default = false;
    return {s0, printed};
  }

  // The initial state must satisfy the constraints that are imposed (the sieve refuses an
  // inconsistent start instead of projecting it, so the assumption "start at rest on the deck"
  // stays what the case says).
  void validate(const std::filesystem::path& file, const toml::table& t) const override {
    const std::string where = input_location(file);
    auto fail = [&](const std::string& key, const std::string& expected, const toml::node* got) {
      std::string msg = where + ": key '" + key + "': expected " + expected;
      if (got) msg += ", got " + format_significant(got->value<double>().value_or(NAN), 17);
      throw InputError(msg);
    };
    const toml::table& ini = *t["initial"].as_table();
    const toml::table& con = *t["constraints"].as_table();
    auto initial = [&](const char* name, double fallback) {
      return ini.contains(name) ? *ini[name].value<double>() : fallback;
    };
    const double s0 = *t["initial"]["s0"].value<double>();
    if (ini.contains("s") && initial("s", s0) != s0)
      fail("initial.s", "the same value as initial.s0 (both give the initial s), or only one of them",
           ini.get("s"));
    const double u0 = *t["parameters"]["u0"].value<double>(), r = *t["parameters"]["r"].value<double>();
    auto near = [](double a, double b) { return std::abs(a - b) <= 1e-12 * (1 + std::abs(a) + std::abs(b)); };
    if (*con["contact"].value<bool>()) {
      if (!near(initial("u", u0), u0))
        fail("initial.u", "parameters.u0 (constraints.contact = true imposes u = u0)", ini.get("u"));
      if (!near(initial("u_d", 0), 0))
        fail("initial.u_d", "0 (constraints.contact = true imposes u = u0)", ini.get("u_d"));
    }
    if (*con["rolling"].value<bool>()) {
      const toml::node* got = ini.get(ini.contains("s_d") ? "s_d" : "phi_d");
      if (*con["rolling_as_printed"].value<bool>()) {
        if (!near(initial("s_d", 0), r * initial("phi_d", 0)))
          fail("initial.s_d",
               "r * initial.phi_d (constraints.rolling = true with rolling_as_printed imposes "
               "s' = r phi')", got);
      } else if (!near(initial("s_d", 0), -r * initial("phi_d", 0))) {
        fail("initial.s_d", "-r * initial.phi_d (constraints.rolling = true imposes s' = -r phi')", got);
      }
    }
    // The geometry: the roller (radius r) on the deck xi in [-a, a] (the desk's outermost
    // attachment, the horizontal spring at xi = a, bounds it), its centre r above the deck
    // surface, and that surface not below the desk's mass centre (u0 - r >= 0).
    const double a = std::abs(*t["parameters"]["a"].value<double>());
    if (!(r < a))
      fail("parameters.r", "a roller radius below the deck's half-length |a| = " +
                               format_significant(a, 6) + " m (the roller must fit on the deck)",
           t["parameters"].as_table()->get("r"));
    if (!(std::abs(initial("s", s0)) <= a))
      fail(ini.contains("s") ? "initial.s" : "initial.s0",
           "a roller position on the deck, |s| <= |a| = " + format_significant(a, 6) + " m",
           ini.get(ini.contains("s") ? "s" : "s0"));
    if (!(u0 - r >= 0))
      fail("parameters.u0", "u0 >= r = " + format_significant(r, 6) +
                                " m (u0 is the roller centre's height over the desk's mass "
                                "centre: the deck surface u0 - r is not below it)",
           t["parameters"].as_table()->get("u0"));
    if (t["contact"]["switching"].value_or(false) && *con["rolling"].value<bool>() &&
        *con["rolling_as_printed"].value<bool>())
      throw InputError(where + ": key 'constraints.rolling_as_printed': expected false with "
                       "contact.switching = true (the printed sign s - r phi is not a contact "
                       "point's sliding velocity, so it cannot be a friction constraint), got true");
    if (*con["lock_theta"].value<bool>()) {
      if (!near(initial("theta", 0), 0))
        fail("initial.theta", "0 (constraints.lock_theta = true imposes theta = 0)", ini.get("theta"));
      if (!near(initial("theta_d", 0), 0))
        fail("initial.theta_d", "0 (constraints.lock_theta = true imposes theta = 0)", ini.get("theta_d"));
    }
  }

  // initial.s0 is the roller's initial position s (unless initial.s gives it; validate checks
  // that they agree), and the roller starts on the deck, u = u0, unless initial.u says otherwise.
  void adjust(const toml::table& t, sim::Setup& s) const override {
    const Layout& at = layout();
    const toml::node_view<const toml::node> ini = t["initial"];
    if (!ini["s"]) s.q0[at.s] = *ini["s0"].value<double>();
    if (!ini["u"]) s.q0[at.u] = s.parameters.at("u0");
    // The printed rolling sign is the model's constraint rolling_printed.
    if (*t["constraints"]["rolling_as_printed"].value<bool>())
      for (auto& name : s.active)
        if (name == "rolling") name = "rolling_printed";
  }

  std::unique_ptr<sim::ClientMonitor> monitor(const sim::Case& c, const sim::Setup& s) const override {
    RunSettings set;
    set.at = layout();
    set.parameters = s.parameters;
    set.a = s.parameters.at("a");
    set.f = s.parameters.at("f");
    set.m2 = s.parameters.at("m2");
    set.g = s.parameters.at("g");
    set.e_n = s.parameters.at("e_n");
    set.s0 = s.q0[set.at.s];
    set.t_end = s.t_end;
    auto active = [&s](const char* name) {
      return std::find(s.active.begin(), s.active.end(), name) != s.active.end();
    };
    set.contact = active("contact");
    set.rolling = active("rolling") || active("rolling_printed");
    set.lock_theta = active("lock_theta");
    set.rolling_as_printed = *c.table["constraints"]["rolling_as_printed"].value<bool>();
    set.switching = s.contact.switching;
    const sim::SummaryWindow w = sim::summary_window(s);
    set.w0 = w.w0;
    set.w1 = w.w1;
    return std::make_unique<SieveMonitor>(std::move(set));
  }

  std::string report(const sim::Case& c, const sim::RunResult& r) const override;

  std::vector<std::string> sweep_columns() const override { return sieve_sweep_columns(); }

  std::map<std::string, double> derived_columns(const sim::RunResult& r,
                                                const sim::Case& c) const override {
    const nlohmann::json& summary = r.additions;
    std::map<std::string, double> out;
    const double f = *c.table["parameters"]["f"].value<double>();
    if (summary.contains("R_u_min_over_weight") && summary["R_u_min_over_weight"].is_number())
      out["contact_margin"] = summary["R_u_min_over_weight"].get<double>();
    if (summary.contains("fstar_max") && summary["fstar_max"].is_number())
      out["rolling_margin"] = 1.0 - summary["fstar_max"].get<double>() / f;
    return out;
  }

  std::vector<sim::PlotFigure> figures(const nlohmann::json& summary,
                                       const std::set<std::string>& columns,
                                       const std::string& table) const override {
    return sieve_figures(summary, columns, table);
  }

  // The desk's motion: the roller's coordinates drift or follow the constraints.
  std::vector<std::string> response_coordinates() const override { return {"x", "y", "theta"}; }

  // `pcsim optimize` maximizes the contact margin min R_u/(m2 g) under these constraints (the
  // paper case, t_end = 10 s, has rolling margin 0.996, amplitude.x 2.36e-5 m, amplitude.theta
  // 1.4e-5 rad):
  //   rolling_margin >= 0.2       rolling (3.2) keeps 20 % of the friction in reserve (issue 6);
  //   amplitude.theta <= 1e-3     the incline vibration stays small (sieve-model.md section 6,
  //                               "theta small"; 1 mrad is ~70x the paper case's amplitude);
  //   amplitude.x >= 2e-5         the sieve must keep vibrating to grind: at least ~85 % of the
  //                               paper case's vertical amplitude, so the optimizer cannot buy
  //                               contact margin by simply switching the vibration off;
  //   amplitude.x <= 1e-4         and at most ~4x of it (spring stroke, desk stresses).
  std::string default_objective() const override { return "contact_margin"; }
  std::vector<sim::SummaryBound> default_constraints() const override {
    return {{"rolling_margin", true, 0.2},
            {"amplitude.theta", false, 1e-3},
            {"amplitude.x", true, 2e-5},
            {"amplitude.x", false, 1e-4}};
  }
};

std::string SieveClient::report(const sim::Case& c, const sim::RunResult& r) const {
  const nlohmann::json s = sim::to_json(r);
  std::ostringstream os;
  char buf[256];
  auto num = [](const nlohmann::json& v, const char* fmt) {
    if (v.is_null()) return std::string("n/a");
    char b[64];
    std::snprintf(b, sizeof b, fmt, v.get<double>());
    return std::string(b);
  };
  os << "pcsim run: case '" << s["case"].get<std::string>() << "' (sieve, "
     << s["model_form"].get<std::string>() << " model, " << s["kernel"].get<std::string>()
     << " kernel, " << s["form"].get<std::string>() << " form, "
     << s.value("methods_used", std::string("radau")) << "), " << s["t_end"].get<double>()
     << " s of motion\n";
  os << "  assumptions (not printed in the paper):";
  int k = 0;
  for (const auto& key : unprinted_parameter_keys()) {
    const auto dot = key.find('.');
    os << (k++ % 6 == 0 ? "\n    " : ", ") << key.substr(dot + 1) << " = "
       << format_significant(*c.table[key.substr(0, dot)][key.substr(dot + 1)].value<double>(), 12);
  }
  os << "\n  constraints:";
  for (const auto& n : s["assumptions"]["constraints"]) os << ' ' << n.get<std::string>();
  if (s.contains("rolling_condition")) os << "; rolling: " << s["rolling_condition"].get<std::string>();
  std::snprintf(buf, sizeof buf, "\n  summary window: t = %.4f .. %.4f s (last %d excitation periods%s)\n",
                s["window"][0].get<double>(), s["window"][1].get<double>(),
                s.value("summary_periods", 0), s["window_clipped"].get<bool>() ? ", clipped to the run" : "");
  os << buf;
  os << "  amplitudes (half peak-to-peak): x = " << num(s["amplitude"]["x"], "%.4g")
     << " m, y = " << num(s["amplitude"]["y"], "%.4g")
     << " m, theta = " << num(s["amplitude"]["theta"], "%.4g") << " rad\n";
  os << "  max |theta| = " << num(s["theta_max_abs"], "%.4g") << " rad in the window ("
     << num(s["theta_max_abs_run"], "%.4g") << " rad over the whole run), mean "
     << num(s["theta_mean"], "%.3g") << " rad\n";
  os << "  contact (3.1), R_u > 0: R_u in [" << num(s["R_u_min"], "%.5g") << ", "
     << num(s["R_u_max"], "%.5g") << "] N; margin min R_u/(m2 g) = "
     << num(s["margins"]["contact"], "%.4f") << "\n";
  os << "  rolling (3.2), f* < f: max f* = " << num(s["fstar_max"], "%.4g")
     << "; margin 1 - max f*/f = " << num(s["margins"]["rolling"], "%.4f") << "\n";
  auto verdict = [&](const char* key, const char* fv) {
    const auto& v = s[key];
    if (v.is_null()) return std::string("not imposed");
    if (v.get<bool>()) return std::string("KEPT over the whole run");
    return "VIOLATED, first at t = " + num(s["first_violation"][fv], "%.6f") + " s";
  };
  os << "  verdict: contact " << verdict("contact_kept", "contact") << "; rolling "
     << verdict("rolling_kept", "rolling") << "\n";
  os << "  closer to violation: " << s["margins"]["closer_to_violation"].get<std::string>()
     << "\n";
  if (s.contains("switching"))
    os << "  (with contact.switching the verdicts say whether the roller ever left the deck or "
          "slipped; what it did instead:)\n"
       << sim::switching_report(r.switching);
  const auto& st = s["stats"];
  os << "  solver: " << st["steps"] << " steps (" << st["accepted"] << " accepted, "
     << st["rejected"] << " rejected), " << st["f_evals"] << " f-evaluations, " << st["jacobians"]
     << " Jacobians, " << st["lu_decompositions"] << " LU; "
     << num(st["wall_seconds"], "%.3f") << " s wall; max constraint residual "
     << num(s["constraint_residual_max"], "%.2g") << "\n";
  return os.str();
}

}  // namespace

std::shared_ptr<const sim::Client> make_sieve_client() { return std::make_shared<const SieveClient>(); }

const std::vector<std::string>& sieve_sweep_columns() {
  static const std::vector<std::string> columns = {
      "amplitude.x", "amplitude.y", "amplitude.theta", "theta_mean", "theta_max_abs",
      "theta_max_abs_run",
      "R_u_min", "R_u_max", "R_u_min_over_weight", "fstar_max",
      "contact_kept", "rolling_kept", "first_violation.contact", "first_violation.rolling",
      "constraint_residual_max",
      "q_end.x", "q_end.y", "q_end.theta", "q_end.s", "q_end.u", "q_end.phi",
      "stats.steps", "stats.accepted", "stats.rejected", "stats.f_evals", "stats.jacobians",
      "stats.lu_decompositions",
      "contact_margin", "rolling_margin"};
  return columns;
}

const std::vector<std::string>& unprinted_parameter_keys() {
  static const std::vector<std::string> keys = {
      "parameters.g",  "parameters.x0", "parameters.y0", "parameters.yc", "parameters.b",
      "parameters.yb", "parameters.a",  "parameters.xc", "parameters.xb", "parameters.u0",
      "initial.s0",    "parameters.f",  "solver.t_end"};
  return keys;
}

}  // namespace pcsim::sieve
