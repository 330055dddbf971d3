// Running a sieve case: simulation, window extremes refined on the dense output, verdicts over
// the whole run, the contracted output files (written atomically), and the engineer's report.
#include "sieve/run.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "common/error.hpp"
#include "mech/simulation.hpp"
#include "sieve/extremes.hpp"
#include "sieve/model.hpp"
#include "sieve/settings.hpp"

namespace pcsim::sieve {

namespace {

constexpr double kPi = 3.14159265358979323846;
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

struct Monitor {
  SieveSettings set;
  double w0 = 0, w1 = 0;                 // summary window
  bool keep_rows = false;
  std::vector<std::array<double, 22>> rows;
  long next_row = 0;
  long last_row = 0;                     // index of the last output time k*dt <= t_end
  RunningMax maxima[sig_count], minima[sig_count];  // minima hold the negated signal
  double theta_integral = 0.0;           // ∫ θ dt over the window (Gauss-Legendre per step)
  double theta_abs_max_run = 0.0;
  double residual_max = 0.0;
  Verdict contact, rolling;
  double ru_prev = 0, ru_scale = 0, fstar_prev = 0;  // at the previous step end

  double row_time(long k) const { return k < last_row ? k * set.output.dt : set.solver.t_end; }

  void add_row(const mech::Sample& s) {
    std::array<double, 22> row{};
    row[0] = s.t;
    for (int i = 0; i < 6; ++i) {
      row[1 + i] = s.q(i);
      row[7 + i] = s.qd(i);
      row[13 + i] = s.R(i);
    }
    row[19] = s.derived(0);
    row[20] = s.residual_pos;
    row[21] = s.residual_vel;
    rows.push_back(row);
  }

  bool contact_violated(const mech::Sample& s) const { return !(s.R(4) > 0); }
  bool rolling_violated(const mech::Sample& s) const { return !(s.derived(0) < set.p.f); }

  // Locates the first violation in (a, b] where a is fine and b violates.
  template <class Pred>
  double locate(const mech::StepView& v, double a, double b, Pred violated) const {
    for (int it = 0; it < 60 && b - a > 1e-13 * std::max(1.0, std::abs(b)); ++it) {
      const double m = 0.5 * (a + b);
      if (violated(v.at(m))) b = m; else a = m;
    }
    return b;
  }

  void whole_run(const mech::StepView& v, const mech::Sample& s, double t_ok) {
    theta_abs_max_run = std::max(theta_abs_max_run, std::abs(s.q(2)));
    residual_max = std::max({residual_max, s.residual_pos, s.residual_vel});
    auto cv = [this](const mech::Sample& x) { return contact_violated(x); };
    auto rv = [this](const mech::Sample& x) { return rolling_violated(x); };
    if (contact.active && !contact.violated() && cv(s))
      contact.first = (s.t == t_ok) ? s.t : locate(v, t_ok, s.t, cv);
    if (rolling.active && !rolling.violated() && rv(s))
      rolling.first = (s.t == t_ok) ? s.t : locate(v, t_ok, s.t, rv);
  }

  void window(const mech::StepView& v) {
    const double a = std::max(v.t_prev, w0), b = v.t;
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
      if (sig == sig_fstar && !rolling.active) continue;
      for (int k = 0; k <= K; ++k) f[k] = signal(smp[k], sig);
      refine_max(s, f, [&](double x) { return signal(v.at(x), sig); }, maxima[sig]);
      if (sig == sig_fstar) continue;  // only the maximum of f* is reported
      for (int k = 0; k <= K; ++k) f[k] = -f[k];
      refine_max(s, f, [&](double x) { return -signal(v.at(x), sig); }, minima[sig]);
    }
    // ∫ θ over [a, b] by 3-point Gauss-Legendre: exact for polynomials of degree <= 5, and the
    // dense output of q on one step is a polynomial of degree 3 (the collocation polynomial).
    const double c = 0.5 * (a + b), hw = 0.5 * (b - a), r = std::sqrt(0.6);
    theta_integral += hw * (5.0 / 9.0 * v.at(c - hw * r).q(2) + 8.0 / 9.0 * v.at(c).q(2) +
                            5.0 / 9.0 * v.at(c + hw * r).q(2));
  }

  bool observe(const mech::StepView& v) {
    if (v.t == v.t_prev) {  // the consistent initial state
      const mech::Sample s0 = v.at(v.t);
      whole_run(v, s0, s0.t);
      ru_prev = s0.R(4);
      ru_scale = std::abs(s0.R(4));
      fstar_prev = s0.derived(0);
      if (keep_rows && next_row <= last_row && row_time(next_row) <= v.t) {
        add_row(s0);
        ++next_row;
      }
      return true;
    }
    // Whole run: the step's end, and its midpoint too when an end is near a violation (R_u
    // below a quarter of its largest value so far, or f* above 3/4 of f): a smooth signal
    // cannot dip from there to the limit and back within one step (~1/25 of a period) unseen.
    const mech::Sample end = v.at(v.t);
    ru_scale = std::max(ru_scale, std::abs(end.R(4)));
    const bool near = (contact.active && std::min(end.R(4), ru_prev) < 0.25 * ru_scale) ||
                      (rolling.active && std::max(end.derived(0), fstar_prev) > 0.75 * set.p.f);
    if (near) {
      const double mid = 0.5 * (v.t_prev + v.t);
      whole_run(v, v.at(mid), v.t_prev);
      whole_run(v, end, mid);
    } else {
      whole_run(v, end, v.t_prev);
    }
    ru_prev = end.R(4);
    fstar_prev = end.derived(0);
    if (v.t > w0) window(v);
    while (keep_rows && next_row <= last_row && row_time(next_row) <= v.t * (1 + 1e-14)) {
      add_row(v.at(std::min(std::max(row_time(next_row), v.t_prev), v.t)));
      ++next_row;
    }
    return true;
  }
};

std::string format_double(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

// Writes `text` to `path` atomically: a temporary file in the same directory, then rename.
void write_atomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp =
      path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw InputError("cannot write " + path.string());
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError("cannot write " + path.string() + ": " + ec.message());
  }
}

std::string csv_text(const Monitor& mon) {
  std::ostringstream os;
  os << "t";
  for (const char* n : kCoordinateNames) os << ',' << n;
  for (const char* n : kCoordinateNames) os << ',' << n << "_d";
  for (const char* n : kCoordinateNames) os << ",R_" << n;
  os << ",fstar,residual_pos,residual_vel\n";
  for (const auto& row : mon.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) os << (i ? "," : "") << format_double(row[i]);
    os << '\n';
  }
  return os.str();
}

nlohmann::json null_if_nan(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json run_case(const Case& c, const RunOptions& options) {
  const SieveSettings set = settings_from_case(c);
  const auto model = make_sieve_model(set, options.model_form);

  mech::SimulationOptions so;
  so.kernel = set.solver.kernel;
  so.form = set.solver.form;
  so.t0 = 0.0;
  so.t_end = set.solver.t_end;
  so.rtol = set.solver.rtol;
  so.atol = set.solver.atol;
  so.h0 = set.solver.h0;
  so.active_constraints = active_constraints(set.constraints);
  so.stabilization = mech::Stabilization::projection;

  Monitor mon;
  mon.set = set;
  const double period = set.p.omega > 0 ? 2 * kPi / set.p.omega : kNaN;
  const double wlen = set.output.summary_periods * period;
  mon.w1 = set.solver.t_end;
  mon.w0 = (std::isfinite(wlen) && wlen < set.solver.t_end) ? set.solver.t_end - wlen : 0.0;
  const bool window_clipped = !(std::isfinite(wlen) && wlen <= set.solver.t_end);
  mon.keep_rows = options.out_dir.has_value();
  mon.last_row = static_cast<long>(std::floor(set.solver.t_end / set.output.dt * (1 + 1e-12)));
  if (mon.last_row * set.output.dt < set.solver.t_end * (1 - 1e-12)) ++mon.last_row;
  mon.contact.active = set.constraints.contact;
  mon.rolling.active = set.constraints.contact && set.constraints.rolling;

  Eigen::VectorXd q0(6), qd0(6);
  for (int i = 0; i < 6; ++i) {
    q0(i) = set.q0[i];
    qd0(i) = set.qd0[i];
  }
  const auto t_start = std::chrono::steady_clock::now();
  const mech::SimulationResult res = mech::simulate(
      *model, q0, qd0, so, [&mon](const mech::StepView& v) { return mon.observe(v); });
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (res.status != mech::SimulationStatus::success) {
    throw NumericalError("case '" + c.name + "': the integration failed at t = " +
                             format_double(res.t) + " s: " + res.message,
                         res.t);
  }

  const double weight = set.p.m2 * set.p.g;
  nlohmann::json j;
  j["case"] = c.name;
  j["model"] = "sieve";
  j["model_form"] = to_string(options.model_form);
  j["kernel"] = to_string(set.solver.kernel);
  j["form"] = to_string(set.solver.form);
  j["t_end"] = set.solver.t_end;
  j["window"] = {mon.w0, mon.w1};
  j["window_clipped"] = window_clipped;
  j["stats"] = {{"steps", res.stats.steps},
                {"accepted", res.stats.accepted},
                {"rejected", res.stats.rejected},
                {"f_evals", res.stats.f_evals},
                {"jacobians", res.stats.jacobians},
                {"lu_decompositions", res.stats.lu_decompositions},
                {"wall_seconds", wall}};
  auto half_pp = [&](int sig) { return 0.5 * (mon.maxima[sig].value + mon.minima[sig].value); };
  j["amplitude"] = {{"x", half_pp(sig_x)}, {"y", half_pp(sig_y)}, {"theta", half_pp(sig_theta)}};
  j["theta_mean"] = mon.theta_integral / (mon.w1 - mon.w0);
  j["theta_max_abs"] = std::max(mon.maxima[sig_theta].value, mon.minima[sig_theta].value);
  j["theta_max_abs_run"] =  // step-end samples, and the refined window extremes
      std::max({mon.theta_abs_max_run, mon.maxima[sig_theta].value, mon.minima[sig_theta].value});
  const double ru_min = -mon.minima[sig_Ru].value, ru_max = mon.maxima[sig_Ru].value;
  j["R_u_min"] = ru_min;
  j["R_u_max"] = ru_max;
  j["R_u_min_over_weight"] = ru_min / weight;
  const double fstar_max = mon.rolling.active ? mon.maxima[sig_fstar].value : kNaN;
  j["fstar_max"] = null_if_nan(fstar_max);
  // A refined window minimum below zero is a violation even if no sample saw it.
  if (mon.contact.active && !mon.contact.violated() && !(ru_min > 0))
    mon.contact.first = mon.minima[sig_Ru].time;
  if (mon.rolling.active && !mon.rolling.violated() && !(fstar_max < set.p.f))
    mon.rolling.first = mon.maxima[sig_fstar].time;
  auto verdict = [](const Verdict& v) {
    return v.active ? nlohmann::json(!v.violated()) : nlohmann::json(nullptr);
  };
  auto when = [](const Verdict& v) { return null_if_nan(v.first); };
  j["contact_kept"] = verdict(mon.contact);
  j["rolling_kept"] = verdict(mon.rolling);
  j["first_violation"] = {{"contact", when(mon.contact)}, {"rolling", when(mon.rolling)}};
  j["constraint_residual_max"] =
      std::max({mon.residual_max, res.residual_pos_max, res.residual_vel_max});
  nlohmann::json qe;
  for (int i = 0; i < 6; ++i) qe[kCoordinateNames[i]] = res.q_end(i);
  j["q_end"] = qe;
  // Margins: (3.1) min R_u/(m2 g) (> 0 kept); (3.2) 1 - max f*/f (> 0 kept).
  const double contact_margin = mon.contact.active ? ru_min / weight : kNaN;
  const double rolling_margin = mon.rolling.active ? 1.0 - fstar_max / set.p.f : kNaN;
  std::string closer = "n/a";
  // Once R_u <= 0 the friction ratio is undefined (f* = inf): the contact is what failed.
  if (mon.contact.active && mon.rolling.active)
    closer = (!(contact_margin > 0) || contact_margin <= rolling_margin) ? "contact (3.1)"
                                                                          : "rolling (3.2)";
  j["margins"] = {{"contact", null_if_nan(contact_margin)},
                  {"rolling", null_if_nan(rolling_margin)},
                  {"closer_to_violation", closer}};
  nlohmann::json as;
  as["note"] =
      "parameters the 1995 paper does not print; values from sieve-model.md section 5 unless "
      "the case file sets them";
  for (const auto& key : unprinted_parameter_keys()) {
    const auto dot = key.find('.');
    as[key] = *c.table[key.substr(0, dot)][key.substr(dot + 1)].value<double>();
  }
  as["initial_state"] = "q = (0, 0, 0, s0, u0, 0), q_d = 0 unless [initial] sets them";
  as["constraints"] = so.active_constraints;
  j["rolling_condition"] = set.constraints.rolling_as_printed
                               ? "s - r phi = const (as printed in (3.2); not physical rolling)"
                               : "s + r phi = const (erratum 7 of (3.2))";
  j["assumptions"] = as;
  j["output_dt"] = set.output.dt;
  j["summary_periods"] = set.output.summary_periods;

  if (options.out_dir) {
    std::error_code ec;
    std::filesystem::create_directories(*options.out_dir, ec);
    if (ec) throw InputError("cannot create output directory " + options.out_dir->string() +
                             ": " + ec.message());
    write_atomically(*options.out_dir / "timeseries.csv", csv_text(mon));
    write_atomically(*options.out_dir / "summary.json", j.dump(2) + "\n");
  }
  return j;
}

std::string human_report(const Case& c, const nlohmann::json& s) {
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
     << " kernel, " << s["form"].get<std::string>() << " form), " << s["t_end"].get<double>()
     << " s of motion\n";
  os << "  assumptions (not printed in the paper):";
  int k = 0;
  for (const auto& key : unprinted_parameter_keys()) {
    const auto dot = key.find('.');
    os << (k++ % 6 == 0 ? "\n    " : ", ") << key.substr(dot + 1) << " = "
       << format_double(*c.table[key.substr(0, dot)][key.substr(dot + 1)].value<double>());
  }
  os << "\n  constraints:";
  for (const auto& n : s["assumptions"]["constraints"]) os << ' ' << n.get<std::string>();
  if (s.contains("rolling_condition")) os << "; rolling: " << s["rolling_condition"].get<std::string>();
  std::snprintf(buf, sizeof buf, "\n  summary window: t = %.4f .. %.4f s (last %d excitation periods%s)\n",
                s["window"][0].get<double>(), s["window"][1].get<double>(),
                s["summary_periods"].get<int>(),
                s["window_clipped"].get<bool>() ? ", clipped to the run" : "");
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
  const auto& st = s["stats"];
  os << "  solver: " << st["steps"] << " steps (" << st["accepted"] << " accepted, "
     << st["rejected"] << " rejected), " << st["f_evals"] << " f-evaluations, " << st["jacobians"]
     << " Jacobians, " << st["lu_decompositions"] << " LU; "
     << num(st["wall_seconds"], "%.3f") << " s wall; max constraint residual "
     << num(s["constraint_residual_max"], "%.2g") << "\n";
  return os.str();
}

}  // namespace pcsim::sieve
