// The sieve client: case keys beyond the generic ones, verdicts over the whole run, the window
// extremes of the paper's signals, the contracted summary keys and the engineer's report.
#include "sieve/run.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "mech/simulation.hpp"
#include "sieve/model.hpp"
#include "sieve/settings.hpp"
#include "sim/extremes.hpp"
#include "sim/switching_summary.hpp"

namespace pcsim::sieve {

using sim::RunningMax;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Signals tracked over the summary window, by index.
enum Signal { sig_x, sig_y, sig_theta, sig_Ru, sig_fstar, sig_count };

double signal(const mech::Sample& smp, int which) {
  switch (which) {
    case sig_x: return smp.q(0);
    case sig_y: return smp.q(1);
    case sig_theta: return smp.q(2);
    case sig_Ru: return smp.R(4);
    default: return smp.derived(0);
  }
}

// A first violation time over the whole run, found on the samples and then located by
// bisection on the dense output of the step where it occurred.
struct Verdict {
  bool active = false;   // the constraint is imposed, so the verdict means something
  double first = kNaN;   // time of the first violation, NaN if none
  bool violated() const { return !std::isnan(first); }
};

class SieveMonitor final : public sim::ClientMonitor {
 public:
  SieveMonitor(SieveSettings set, double w0, double w1, bool switching, double e_n)
      : set_(std::move(set)), w0_(w0), w1_(w1), switching_(switching), e_n_(e_n) {
    contact_.active = set_.constraints.contact;
    rolling_.active = set_.constraints.contact && set_.constraints.rolling;
  }

  bool observe(const mech::StepView& v) override {
    if (v.t == v.t_prev) {  // the consistent initial state
      const mech::Sample s0 = v.at(v.t);
      whole_run(v, s0, s0.t);
      ru_prev_ = s0.R(4);
      ru_scale_ = std::abs(s0.R(4));
      fstar_prev_ = s0.derived(0);
      return true;
    }
    // The roller's contact point must stay on the deck, xi in [-a, a] (docs/sieve.md): beyond
    // it the model (a roller on an endless plane) no longer describes the machine.
    const double deck = std::abs(set_.p.a);
    auto off_deck = [deck](const mech::Sample& x) { return std::abs(x.q(3)) > deck; };
    if (off_deck(v.sample(v.t))) {
      double lo = v.t_prev, hi = v.t;
      for (int it = 0; it < 60 && hi - lo > 1e-13 * std::max(1.0, std::abs(hi)); ++it) {
        const double m = 0.5 * (lo + hi);
        if (off_deck(v.sample(m))) hi = m; else lo = m;
      }
      stop_t_ = hi;
      stop_reason_ = "the roller left the deck at t = " + format_significant(hi, 9) +
                     " s (|s| > a = " + format_significant(deck, 6) + " m)";
      return false;
    }
    // Whole run: the step's end, and its midpoint too when an end is near a violation (R_u
    // below a quarter of its largest value so far, or f* above 3/4 of f): a smooth signal
    // cannot dip from there to the limit and back within one step (~1/25 of a period) unseen.
    const mech::Sample end = v.at(v.t);
    ru_scale_ = std::max(ru_scale_, std::abs(end.R(4)));
    const bool near = (contact_.active && std::min(end.R(4), ru_prev_) < 0.25 * ru_scale_) ||
                      (rolling_.active && std::max(end.derived(0), fstar_prev_) > 0.75 * set_.p.f);
    if (near) {
      const double mid = 0.5 * (v.t_prev + v.t);
      whole_run(v, v.at(mid), v.t_prev);
      whole_run(v, end, mid);
    } else {
      whole_run(v, end, v.t_prev);
    }
    ru_prev_ = end.R(4);
    fstar_prev_ = end.derived(0);
    if (v.t > w0_) window(v);
    return true;
  }

  double stop_time() const override { return stop_t_; }
  std::string stop_reason() const override { return stop_reason_; }

  void finish(const mech::SimulationResult& res, sim::RunResult& result) override {
    nlohmann::json& j = result.additions;
    const double weight = set_.p.m2 * set_.p.g;
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
    if (rolling_.active && !rolling_.violated() && !(fstar_max < set_.p.f))
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
    const double rolling_margin = rolling_.active ? 1.0 - fstar_max / set_.p.f : kNaN;
    std::string closer = "n/a";
    // Once R_u <= 0 the friction ratio is undefined (f* = inf): the contact is what failed.
    if (contact_.active && rolling_.active)
      closer = (!(contact_margin > 0) || contact_margin <= rolling_margin) ? "contact (3.1)"
                                                                            : "rolling (3.2)";
    j["margins"] = {{"contact", null_if_nan(contact_margin)},
                    {"rolling", null_if_nan(rolling_margin)},
                    {"closer_to_violation", closer}};
    std::vector<std::string> active;
    if (set_.constraints.contact) active.push_back("contact");
    if (set_.constraints.rolling) active.push_back("rolling");
    if (set_.constraints.lock_theta) active.push_back("lock_theta");
    nlohmann::json as;
    as["note"] =
        "parameters the 1995 paper does not print: the project's documented defaults "
        "(docs/sieve-model.md, section 5) unless the case file sets them";
    as["parameters.g"] = set_.p.g;
    as["parameters.x0"] = set_.p.x0;
    as["parameters.y0"] = set_.p.y0;
    as["parameters.yc"] = set_.p.yc;
    as["parameters.b"] = set_.p.b;
    as["parameters.yb"] = set_.p.yb;
    as["parameters.a"] = set_.p.a;
    as["parameters.xc"] = set_.p.xc;
    as["parameters.xb"] = set_.p.xb;
    as["parameters.u0"] = set_.p.u0;
    as["initial.s0"] = set_.q0[3];
    as["parameters.f"] = set_.p.f;
    as["solver.t_end"] = set_.solver.t_end;
    as["initial_state"] = "q = (0, 0, 0, s0, u0, 0), q_d = 0 unless [initial] sets them";
    as["constraints"] = active;
    if (switching_) as["parameters.e_n"] = e_n_;  // the landing's restitution (issue 12)
    j["assumptions"] = as;
    j["rolling_condition"] = set_.constraints.rolling_as_printed
                                 ? "s - r phi = const (as printed in (3.2); not physical rolling)"
                                 : "s + r phi = const (erratum 7 of (3.2))";
  }

 private:
  static nlohmann::json null_if_nan(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  }

  bool contact_violated(const mech::Sample& s) const { return !(s.R(4) > 0); }
  bool rolling_violated(const mech::Sample& s) const {
    // With switching, a roller in flight has no contact force at all (f* = 0/0): nothing rolls
    // or slips there; its rolling verdict fails only when it slides (f* = f).
    if (switching_ && s.R(4) == 0.0 && s.R(3) == 0.0) return false;
    return !(s.derived(0) < set_.p.f);
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
    theta_abs_max_run_ = std::max(theta_abs_max_run_, std::abs(s.q(2)));
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
    const double th0 = v.sample(c - hw * r).q(2);
    const double th1 = v.sample(c).q(2);
    const double th2 = v.sample(c + hw * r).q(2);
    theta_integral_ += hw * (5.0 / 9.0 * th0 + 8.0 / 9.0 * th1 + 5.0 / 9.0 * th2);
  }

  SieveSettings set_;
  double w0_, w1_;
  bool switching_ = false;  // contact.switching (issue 12)
  double e_n_ = 0.0;
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

  void adjust(const toml::table& t, sim::Setup& s) const override {
    const SieveSettings set = settings_from_table(t);
    for (int i = 0; i < 6; ++i) {
      s.q0[i] = set.q0[i];
      s.qd0[i] = set.qd0[i];
    }
    // The printed rolling sign is the model's constraint rolling_printed.
    if (set.constraints.rolling_as_printed)
      for (auto& name : s.active)
        if (name == "rolling") name = "rolling_printed";
  }

  std::unique_ptr<sim::ClientMonitor> monitor(const sim::Case& c, const sim::Setup& s) const override {
    const SieveSettings set = settings_from_case(c);
    double w0 = 0.0;
    if (s.window.periods > 0) {
      const double len = s.window.periods * s.period;
      w0 = (std::isfinite(len) && len < s.t_end) ? s.t_end - len : 0.0;
    } else {
      w0 = s.window.time < s.t_end ? s.t_end - s.window.time : 0.0;
    }
    return std::make_unique<SieveMonitor>(set, w0, s.t_end, s.contact.switching,
                                          c.table["parameters"]["e_n"].value_or(0.0));
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

SieveSettings settings_from_table(const toml::table& t) {
  SieveSettings s;
  auto par = [&](const char* name) { return *t["parameters"][name].value<double>(); };
  SieveParameters& p = s.p;
  p.m0 = par("m0"); p.m1 = par("m1"); p.m2 = par("m2");
  p.J0 = par("J0"); p.J1 = par("J1"); p.J2 = par("J2");
  p.r = par("r"); p.e = par("e");
  p.cx = par("cx"); p.cy = par("cy"); p.ctheta = par("ctheta");
  p.bx = par("bx"); p.by = par("by"); p.btheta = par("btheta");
  p.omega = par("omega"); p.g = par("g");
  p.x0 = par("x0"); p.y0 = par("y0"); p.xc = par("xc"); p.yc = par("yc");
  p.xb = par("xb"); p.yb = par("yb"); p.a = par("a"); p.b = par("b");
  p.u0 = par("u0"); p.f = par("f");
  s.constraints.contact = *t["constraints"]["contact"].value<bool>();
  s.constraints.rolling = *t["constraints"]["rolling"].value<bool>();
  s.constraints.lock_theta = *t["constraints"]["lock_theta"].value<bool>();
  s.constraints.rolling_as_printed = *t["constraints"]["rolling_as_printed"].value<bool>();
  const toml::node_view<const toml::node> ini = t["initial"];
  const double s0 = *ini["s0"].value<double>();
  const std::array<double, 6> q_default = {0, 0, 0, s0, p.u0, 0};
  for (int i = 0; i < 6; ++i) {
    const std::string name = kCoordinateNames[i];
    s.q0[i] = ini[name].value_or(q_default[i]);
    s.qd0[i] = ini[name + "_d"].value_or(0.0);
  }
  s.solver.kernel = *parse_kernel(*t["solver"]["kernel"].value<std::string>());
  s.solver.form = *t["solver"]["form"].value<std::string>() == "ode" ? Form::ode : Form::dae;
  s.solver.rtol = *t["solver"]["rtol"].value<double>();
  s.solver.atol = *t["solver"]["atol"].value<double>();
  s.solver.t_end = *t["solver"]["t_end"].value<double>();
  s.solver.h0 = *t["solver"]["h0"].value<double>();
  s.output.dt = *t["output"]["dt"].value<double>();
  s.output.summary_periods = static_cast<int>(t["output"]["summary_periods"].value_or(int64_t{5}));
  return s;
}

const std::vector<std::string>& unprinted_parameter_keys() {
  static const std::vector<std::string> keys = {
      "parameters.g",  "parameters.x0", "parameters.y0", "parameters.yc", "parameters.b",
      "parameters.yb", "parameters.a",  "parameters.xc", "parameters.xb", "parameters.u0",
      "initial.s0",    "parameters.f",  "solver.t_end"};
  return keys;
}

}  // namespace pcsim::sieve
