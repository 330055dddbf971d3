// `pcsim modes` for a case (see modes_case.hpp).
#include "modes/modes_case.hpp"
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include <Eigen/SVD>

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "mech/equilibrium.hpp"
#include "mech/projection.hpp"

namespace pcsim::modes {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Points of the period average (excitation "off"): the periodic trapezoid rule, exact for
/// trigonometric polynomials in t of degree < 64 (as the static equilibrium averages).
constexpr int kAverageSamples = 64;

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string f(double v, int d = 6) { return format_significant(v, d); }

/// The [modes] table's options: excitation ("off" or a phase in rad, as a number or a string)
/// and cyclic (coordinate names), with the command line's overrides.
void read_modes_table(const sim::Case& c, const ModesOptions& o, std::string& excitation,
                      std::vector<std::string>& cyclic) {
  const std::string w = input_location(c.source);
  excitation = "off";
  if (const toml::table* t = c.table["modes"].as_table()) {
    for (const auto& [k, v] : *t) {
      const std::string key(k.str());
      if (key == "excitation") {
        if (auto s = v.value_exact<std::string>()) excitation = *s;
        else if (auto d = v.value<double>(); d && (v.is_floating_point() || v.is_integer())) excitation = format_number(*d);
        else throw InputError(w + ": key 'modes.excitation': expected \"off\" or the excitation's phase in rad (a number)");
      } else if (key == "cyclic") {
        const toml::array* a = v.as_array();
        if (!a) throw InputError(w + ": key 'modes.cyclic': expected an array of coordinate names, e.g. [\"phi\"]");
        for (const auto& e : *a) {
          auto s = e.value_exact<std::string>();
          if (!s) throw InputError(w + ": key 'modes.cyclic': expected an array of coordinate names (strings)");
          cyclic.push_back(*s);
        }
      } else {
        throw InputError(w + ": key 'modes." + key + "': expected a known key of [modes]: excitation, cyclic");
      }
    }
  }
  if (o.excitation) excitation = *o.excitation;
  if (o.cyclic) cyclic = *o.cyclic;
}

}  // namespace

Reference case_reference(const sim::Case& c, const ModesOptions& o) {
  const std::string w = input_location(c.source);
  const sim::Setup& set = c.setup;
  Reference r;
  std::string excitation;
  read_modes_table(c, o, excitation, r.cyclic);
  r.model = c.model->instantiate(set.parameters, set.q0, 0.0, c.table, "");
  if (!r.model->has_tangents())
    throw InputError(w + ": the " + c.model->origin() + " instance has no exact tangents, which pcsim modes "
                     "needs (it never falls back to finite differences): only models from model files have them");
  LinearizeInput& in = r.input;
  in.model = r.model.get();
  std::string msg;
  if (mech::resolve_constraints(*r.model, set.active, in.active, msg) != mech::ModelIssue::none)
    throw InputError(w + ": " + msg);
  for (const auto& name : r.cyclic) {
    const int i = c.model->coordinate_index(name);
    if (i < 0) {
      std::string known;
      for (const auto& k : c.model->coordinates()) known += (known.empty() ? "" : " ") + k;
      throw InputError(w + ": key 'modes.cyclic': expected coordinates of the " + c.model->origin() + " (" + known +
                       "), got '" + name + "'");
    }
    if (std::find(in.cyclic.begin(), in.cyclic.end(), i) != in.cyclic.end())
      throw InputError(w + ": key 'modes.cyclic': '" + name + "' is named twice");
    in.cyclic.push_back(i);
  }
  // The excitation.
  r.period = set.period;
  const bool periodic = std::isfinite(r.period) && r.period > 0;
  if (excitation == "off") {
    if (periodic) {
      r.excitation = "off";
      in.times.clear();
      for (int k = 0; k < kAverageSamples; ++k) in.times.push_back(r.period * k / kAverageSamples);
      r.excitation_text = "off: the model averaged over one excitation period (" + f(r.period, 6) +
                          " s, " + std::to_string(kAverageSamples) +
                          " equally spaced times; the Jacobian and the forces are their means, so a forcing "
                          "periodic in t drops out exactly and a periodic coefficient enters with its mean)";
    } else {
      r.excitation = "none";
      r.period = kNaN;
      in.times = {0.0};
      r.excitation_text = "none declared: the model at t = 0 (no [model] period), d/dt dropped";
    }
  } else {
    char* end = nullptr;
    const double phase = std::strtod(excitation.c_str(), &end);
    if (excitation.empty() || *end != '\0' || !std::isfinite(phase))
      throw InputError(w + ": key 'modes.excitation': expected \"off\" or the excitation's phase in rad (a finite "
                       "number), got '" + excitation.substr(0, 80) + "'");
    if (!periodic)
      throw InputError(w + ": key 'modes.excitation': a phase needs an excitation period, and the " +
                       c.model->origin() + " declares none ([model] period); use \"off\"");
    r.excitation = "phase";
    r.phase = phase;
    const double t = r.period * phase / (2 * kPi);
    in.times = {t};
    r.excitation_text = "held at the phase " + f(phase, 6) + " rad of the period " + f(r.period, 6) +
                        " s: the model frozen at t = " + f(t, 6) + " s, d/dt dropped";
  }
  // The state.
  const int n = r.model->n();
  if (set.equilibrium_start) {
    if (!r.cyclic.empty())
      throw InputError(w + ": key 'initial.from': a steady motion ([modes] cyclic) is the case's initial state with "
                       "the cyclic rates in [initial]; \"equilibrium\" is a rest state");
    mech::EquilibriumOptions eo;
    if (r.excitation == "off") {
      eo.period = r.period;
      eo.samples = kAverageSamples;
    } else {
      eo.t0 = in.times.front();
    }
    // The slow coordinates are held at their value (as pcsim steady holds them), unless the
    // active holonomic constraints already fix them (holding one twice is singular).
    std::vector<int> hol;
    for (int i : in.active)
      if (r.model->constraints()[static_cast<std::size_t>(i)].kind == mech::ConstraintKind::holonomic) hol.push_back(i);
    Eigen::MatrixXd gh(hol.size(), n);
    Eigen::VectorXd g0h(hol.size()), gah(hol.size());
    if (!hol.empty()) r.model->constraint_rows(hol, in.times.front(), set.q0, Eigen::VectorXd::Zero(n), gh, g0h, gah);
    auto rank = [](const Eigen::MatrixXd& A) {
      if (A.rows() == 0) return 0;
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A);
      const Eigen::VectorXd sv = svd.singularValues();
      int k = 0;
      for (Eigen::Index i = 0; i < sv.size(); ++i) k += sv[i] > 1e-10 * std::max(1.0, sv[0]);
      return k;
    };
    const int r0 = rank(gh);
    for (const auto& name : c.model->slow_coordinates()) {
      const int i = c.model->coordinate_index(name);
      if (i < 0) continue;
      Eigen::MatrixXd ge(gh.rows() + 1, n);
      ge.topRows(gh.rows()) = gh;
      ge.row(gh.rows()).setZero();
      ge(gh.rows(), i) = 1.0;
      if (rank(ge) > r0) eo.held.push_back(i);
    }
    const mech::EquilibriumResult e = mech::static_equilibrium(*r.model, in.active, set.q0, eo);
    if (e.issue != mech::ModelIssue::none)
      throw NumericalError("case '" + c.name + "': initial.from = \"equilibrium\": " + e.message, in.times.front());
    in.q = e.q;
    in.qd = Eigen::VectorXd::Zero(n);
    in.extra_force = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < eo.held.size() && static_cast<Eigen::Index>(k) < e.holding_force.size(); ++k)
      in.extra_force[eo.held[k]] = e.holding_force[static_cast<Eigen::Index>(k)];
    r.source = "static equilibrium";
  } else {
    in.q = set.q0;
    in.qd = set.qd0;
    r.source = "initial state";
  }
  return r;
}

nlohmann::json case_modes(const sim::Case& c, const ModesOptions& o, Linearization* out) {
  const Reference r = case_reference(c, o);
  const Linearization L = linearize(r.input);
  const auto& coords = c.model->coordinates();
  const int n = static_cast<int>(coords.size());
  const std::string problem = rest_problem(L, coords, r.input.cyclic);
  if (!problem.empty())
    throw InputError(input_location(c.source) + ": the " + r.source + " is not a " +
                     (r.cyclic.empty() ? "rest state" : "steady motion") + ": " + problem +
                     (r.source == "initial state" && r.cyclic.empty()
                          ? " (initial.from = \"equilibrium\" starts from the static equilibrium)"
                          : ""));
  nlohmann::json j;
  j["case"] = c.name;
  j["model"] = c.model->name();
  j["coordinates"] = coords;
  j["parameters"] = c.setup.parameters;  // the values linearized at (pcsim animate draws with them)
  nlohmann::json q = nlohmann::json::object(), qd = nlohmann::json::object();
  for (int i = 0; i < n; ++i) {
    q[coords[i]] = r.input.q[i];
    qd[coords[i] + "_d"] = r.input.qd[i];
  }
  j["reference"] = {{"kind", r.cyclic.empty() ? "rest state" : "steady motion"},
                    {"source", r.source},
                    {"cyclic", r.cyclic},
                    {"q", q},
                    {"qd", qd}};
  if (r.input.extra_force.size() == n && r.input.extra_force.cwiseAbs().maxCoeff() > 0) {
    nlohmann::json h = nlohmann::json::object();
    for (int i = 0; i < n; ++i)
      if (r.input.extra_force[i] != 0) h[coords[i]] = r.input.extra_force[i];
    j["reference"]["holding_forces"] = h;
  }
  j["excitation"] = {{"mode", r.excitation},
                     {"period", num(r.period)},
                     {"frequency_rad_s", num(std::isfinite(r.period) ? 2 * kPi / r.period : kNaN)},
                     {"meaning", r.excitation_text}};
  if (r.excitation == "phase") j["excitation"]["phase"] = r.phase;
  nlohmann::json active = nlohmann::json::array();
  for (int i : r.input.active) active.push_back(r.model->constraints()[static_cast<std::size_t>(i)].name);
  j["tangent_space"] = {
      {"state_dimension", 2 * n},
      {"constraints", active},
      {"holonomic_rows", L.holonomic_rows},
      {"velocity_rows", L.velocity_rows},
      {"rank", L.rank},
      {"dimension", L.dimension},
      {"rank_tol", r.input.rank_tol},
      {"smallest_kept_singular_value", num(L.rank_gap_below)},
      {"largest_dropped_singular_value", num(L.rank_gap_above)},
      {"invariance_check", L.invariance},
      {"how", "null space of C = [[g_h, 0], [d(g q_d + g0)/dq, g]] (holonomic rows' positions, every active row's "
              "velocity form; 2n columns) by an SVD of C with unit rows: singular values <= rank_tol are zero; "
              "B an orthonormal basis of null(C), A = B^T J B with J the exact Jacobian of the ODE form; "
              "invariance_check = |J B - B A|_F / max(|J|_F, 1)"}};
  nlohmann::json acc = nlohmann::json::object();
  for (int i = 0; i < n; ++i) acc[coords[i] + "_dd"] = L.qdd[i];
  j["rest_check"] = {{"residual", L.residual}, {"force_scale", L.force_scale}, {"tolerance", r.input.rest_tol},
                     {"accelerations", acc}};
  nlohmann::json ev = nlohmann::json::array();
  double max_re = -std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k < L.eigenvalues.size(); ++k) {
    ev.push_back({{"re", L.eigenvalues[k].real()}, {"im", L.eigenvalues[k].imag()}});
    max_re = std::max(max_re, L.eigenvalues[k].real());
  }
  j["eigenvalues"] = ev;
  nlohmann::json modes = nlohmann::json::array();
  int zeros = 0;
  for (std::size_t k = 0; k < L.modes.size(); ++k) {
    const Mode& m = L.modes[k];
    zeros += m.kind == "rigid-body" || m.kind == "cyclic";
    nlohmann::json shape = nlohmann::json::object();
    for (int i = 0; i < n; ++i)
      shape[coords[i]] = {{"re", m.shape[i].real()},
                          {"im", m.shape[i].imag()},
                          {"abs", std::abs(m.shape[i])},
                          {"phase_deg", std::arg(m.shape[i]) * 180 / kPi}};
    nlohmann::json dom = nlohmann::json::array();
    for (int i : m.dominant) dom.push_back(coords[i]);
    modes.push_back({{"mode", k + 1},
                     {"kind", m.kind},
                     {"pair", m.pair},
                     {"re", m.lambda.real()},
                     {"im", m.lambda.imag()},
                     {"natural_frequency_rad_s", m.natural_frequency},
                     {"natural_frequency_hz", m.natural_frequency / (2 * kPi)},
                     {"damped_frequency_rad_s", m.damped_frequency},
                     {"damping_ratio", num(m.damping_ratio)},
                     {"dominant", dom},
                     {"shape", shape}});
  }
  j["modes"] = modes;
  nlohmann::json und = nlohmann::json::array();
  for (double w2 : L.omega2)
    und.push_back({{"omega2", w2},
                   {"omega_rad_s", num(w2 >= 0 ? std::sqrt(w2) : kNaN)},
                   {"frequency_hz", num(w2 >= 0 ? std::sqrt(w2) / (2 * kPi) : kNaN)}});
  j["undamped"] = {{"frequencies", und},
                   {"how", "eigenvalues w^2 of Mr^-1 Kr, Mr = N^T M N, Kr = -N^T M (dq_dd/dq) N, N an orthonormal basis of "
                           "the null space of every active row g: the velocity-dependent terms (damping, gyroscopic) "
                           "dropped; w^2 < 0: statically unstable"}};
  j["zero_tolerance"] = L.zero_tol;
  j["zero_modes"] = zeros;
  j["max_real_part"] = num(L.eigenvalues.size() ? max_re : kNaN);
  j["stable"] = L.stable;
  if (out) *out = L;
  return j;
}

std::string modes_csv(const nlohmann::json& j) {
  std::ostringstream os;
  const auto coords = j["coordinates"].get<std::vector<std::string>>();
  os << "mode,kind,re,im,natural_frequency_rad_s,natural_frequency_hz,damped_frequency_rad_s,damping_ratio,dominant";
  for (const auto& c : coords) os << "," << c << "_abs," << c << "_phase_deg";
  os << "\n";
  auto v = [](const nlohmann::json& x) { return x.is_null() ? std::string() : format_number(x.get<double>()); };
  for (const auto& m : j["modes"]) {
    std::string dom;
    for (const auto& d : m["dominant"]) dom += (dom.empty() ? "" : " ") + d.get<std::string>();
    os << m["mode"].get<int>() << "," << m["kind"].get<std::string>() << "," << v(m["re"]) << "," << v(m["im"]) << ","
       << v(m["natural_frequency_rad_s"]) << "," << v(m["natural_frequency_hz"]) << ","
       << v(m["damped_frequency_rad_s"]) << "," << v(m["damping_ratio"]) << "," << dom;
    for (const auto& c : coords) os << "," << v(m["shape"][c]["abs"]) << "," << v(m["shape"][c]["phase_deg"]);
    os << "\n";
  }
  return os.str();
}

nlohmann::json modes_case(const sim::Case& c, const ModesOptions& o) {
  // The directory is taken (locked, checked) before the work, and written only when it is done.
  std::unique_ptr<OutputDirectory> out;
  if (o.out_dir) out = std::make_unique<OutputDirectory>(*o.out_dir, "modes");
  nlohmann::json j = case_modes(c, o);
  if (out) {
    out->write("modes.json", j.dump(2) + "\n");
    out->write("modes.csv", modes_csv(j));
    // The model the modes are of, as a model file, written as pcsim run writes it (pcsim
    // animate draws the mode shapes with its [model.draw] table).
    const std::string model_text = c.model->definition_text();
    if (!model_text.empty()) {
      std::string origin = c.model->origin();
      std::replace_if(origin.begin(), origin.end(), [](char ch) { return ch == '\n' || ch == '\r'; }, ' ');
      out->write("model.toml", "# pcsim modes: the " + origin + "\n" + model_text);
    }
    out->commit();
  }
  return j;
}

std::string modes_report(const sim::Case& c, const nlohmann::json& j) {
  std::ostringstream os;
  const auto& ref = j["reference"];
  os << "pcsim modes: case '" << j["case"].get<std::string>() << "' (" << c.model->origin() << "), about the "
     << ref["kind"].get<std::string>() << " at the case's " << ref["source"].get<std::string>();
  if (!ref["cyclic"].empty()) {
    os << " (cyclic:";
    for (const auto& name : ref["cyclic"])
      os << " " << name.get<std::string>() << "_d = " << f(ref["qd"][name.get<std::string>() + "_d"].get<double>(), 6);
    os << ")";
  }
  os << "\n  excitation " << j["excitation"]["meaning"].get<std::string>() << "\n";
  if (ref.contains("holding_forces"))
    for (const auto& [name, v] : ref["holding_forces"].items())
      if (std::abs(v.get<double>()) > 1e-12 * j["rest_check"]["force_scale"].get<double>())
      os << "  slow coordinate " << name << " held by the constant force " << f(v.get<double>(), 4)
         << " (as pcsim steady holds it)\n";
  const auto& ts = j["tangent_space"];
  os << "  tangent space: dimension " << ts["dimension"].get<int>() << " of the " << ts["state_dimension"].get<int>()
     << " states (q, q_d): C has " << ts["holonomic_rows"].get<int>() << " holonomic position row(s) and "
     << ts["velocity_rows"].get<int>() << " velocity-form row(s), rank " << ts["rank"].get<int>()
     << " (SVD of unit rows, cut at " << f(ts["rank_tol"].get<double>(), 2) << ": smallest kept "
     << (ts["smallest_kept_singular_value"].is_null() ? std::string("-") : f(ts["smallest_kept_singular_value"].get<double>(), 3))
     << ", largest dropped "
     << (ts["largest_dropped_singular_value"].is_null() ? std::string("-") : f(ts["largest_dropped_singular_value"].get<double>(), 3))
     << "); invariance |JB - BA|/|J| = " << f(ts["invariance_check"].get<double>(), 3) << "\n";
  os << "  rest check: force residual " << f(j["rest_check"]["residual"].get<double>(), 3) << " of the force scale "
     << f(j["rest_check"]["force_scale"].get<double>(), 3) << "\n";
  const double wex = j["excitation"]["frequency_rad_s"].is_null() ? kNaN : j["excitation"]["frequency_rad_s"].get<double>();
  os << "  modes (lambda = sigma +- i omega_d; omega_n = |lambda|; coordinates of different units are compared as "
        "numbers):\n";
  char b[256];
  std::snprintf(b, sizeof b, "    %3s  %-11s %13s %13s %13s %11s %9s  %s\n", "#", "kind", "sigma (1/s)", "omega_d (rad/s)",
                "omega_n(rad/s)", "f_n (Hz)", "zeta", "dominant coordinates");
  os << b;
  for (const auto& m : j["modes"]) {
    std::string dom;
    for (const auto& d : m["dominant"]) {
      const std::string name = d.get<std::string>();
      dom += (dom.empty() ? "" : ", ") + name + " " + f(m["shape"][name]["abs"].get<double>(), 2);
    }
    std::snprintf(b, sizeof b, "    %3d  %-11s %13.6g %13.6g %13.6g %11.5g %9s  %s\n", m["mode"].get<int>(),
                  m["kind"].get<std::string>().c_str(), m["re"].get<double>(), m["im"].get<double>(),
                  m["natural_frequency_rad_s"].get<double>(), m["natural_frequency_hz"].get<double>(),
                  m["damping_ratio"].is_null() ? "-" : f(m["damping_ratio"].get<double>(), 4).c_str(), dom.c_str());
    os << b;
  }
  os << "  undamped frequencies (damping and gyroscopic terms dropped), rad/s:";
  for (const auto& u : j["undamped"]["frequencies"])
    os << " " << (u["omega_rad_s"].is_null() ? "i*" + f(std::sqrt(-u["omega2"].get<double>()), 5) + " (unstable)"
                                              : f(u["omega_rad_s"].get<double>(), 6));
  os << "\n";
  if (std::isfinite(wex)) {
    double below = 0, above = 0;
    for (const auto& m : j["modes"])
      if (m["kind"] == "oscillatory") (m["natural_frequency_rad_s"].get<double>() < wex ? below : above) += 1;
    os << "  excitation frequency " << f(wex, 6) << " rad/s: " << below << " oscillatory mode(s) below it, " << above
       << " above\n";
  }
  os << "  the reference is " << (j["stable"].get<bool>() ? "STABLE" : "UNSTABLE") << " (largest real part "
     << f(j["max_real_part"].get<double>(), 4) << "; |lambda| <= " << f(j["zero_tolerance"].get<double>(), 2)
     << " counts as zero";
  if (j["zero_modes"].get<int>() > 0) os << "; " << j["zero_modes"].get<int>() << " zero mode(s): marginal";
  os << ")\n";
  return os.str();
}

VarySpec parse_vary(const std::string& text) {
  const std::string help = "--vary '" + text.substr(0, 120) + "': expected KEY=START:STOP:COUNT, e.g. parameters.cx=2e4:8e4:31";
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError(help);
  VarySpec v;
  v.key = text.substr(0, eq);
  std::string rest = text.substr(eq + 1);
  std::vector<std::string> parts;
  std::size_t p = 0;
  while (true) {
    const auto c = rest.find(':', p);
    parts.push_back(rest.substr(p, c == std::string::npos ? std::string::npos : c - p));
    if (c == std::string::npos) break;
    p = c + 1;
  }
  if (parts.size() != 3) throw InputError(help);
  auto number = [&](const std::string& s, const char* what) {
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(x)) throw InputError(help + " (" + what + ": not a finite number)");
    return x;
  };
  v.start = number(parts[0], "START");
  v.stop = number(parts[1], "STOP");
  const double cnt = number(parts[2], "COUNT");
  if (!(cnt >= 2 && cnt <= 10000 && cnt == std::floor(cnt))) throw InputError(help + " (COUNT: an integer 2 .. 10000)");
  v.count = static_cast<int>(cnt);
  return v;
}

namespace {
std::vector<int> hungarian(const Eigen::MatrixXd& cost_matrix);
}

std::vector<int> pair_by_continuity(const std::vector<std::complex<double>>& pred,
                                    const std::vector<std::complex<double>>& next) {
  Eigen::MatrixXd cost(pred.size(), next.size());
  for (std::size_t i = 0; i < pred.size(); ++i)
    for (std::size_t j = 0; j < next.size(); ++j) cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = std::abs(pred[i] - next[j]);
  return hungarian(cost);
}

std::vector<int> pair_by_continuity(const std::vector<std::complex<double>>& pred,
                                    const std::vector<std::complex<double>>& next, const Eigen::MatrixXcd& U,
                                    const Eigen::MatrixXcd& W, const std::vector<double>& scales) {
  Eigen::MatrixXd cost(pred.size(), next.size());
  for (std::size_t i = 0; i < pred.size(); ++i)
    for (std::size_t j = 0; j < next.size(); ++j) {
      const double overlap = std::min(1.0, std::abs(U.col(static_cast<Eigen::Index>(i)).dot(W.col(static_cast<Eigen::Index>(j)))));
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = std::abs(pred[i] - next[j]) + scales[i] * (1.0 - overlap);
    }
  return hungarian(cost);
}

namespace {

std::vector<int> hungarian(const Eigen::MatrixXd& C) {
  // The Hungarian method (potentials and augmenting paths, O(m^3)) on the cost C(i, j).
  const int m = static_cast<int>(C.rows());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(static_cast<std::size_t>(m + 1)), v(static_cast<std::size_t>(m + 1));
  std::vector<int> p(static_cast<std::size_t>(m + 1)), way(static_cast<std::size_t>(m + 1));
  auto cost = [&](int i, int jj) { return C(i - 1, jj - 1); };
  for (int i = 1; i <= m; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(static_cast<std::size_t>(m + 1), inf);
    std::vector<char> used(static_cast<std::size_t>(m + 1), 0);
    do {
      used[static_cast<std::size_t>(j0)] = 1;
      const int i0 = p[static_cast<std::size_t>(j0)];
      double delta = inf;
      int j1 = 0;
      for (int jj = 1; jj <= m; ++jj) {
        if (used[static_cast<std::size_t>(jj)]) continue;
        const double cur = cost(i0, jj) - u[static_cast<std::size_t>(i0)] - v[static_cast<std::size_t>(jj)];
        if (cur < minv[static_cast<std::size_t>(jj)]) {
          minv[static_cast<std::size_t>(jj)] = cur;
          way[static_cast<std::size_t>(jj)] = j0;
        }
        if (minv[static_cast<std::size_t>(jj)] < delta) {
          delta = minv[static_cast<std::size_t>(jj)];
          j1 = jj;
        }
      }
      for (int jj = 0; jj <= m; ++jj) {
        if (used[static_cast<std::size_t>(jj)]) {
          u[static_cast<std::size_t>(p[static_cast<std::size_t>(jj)])] += delta;
          v[static_cast<std::size_t>(jj)] -= delta;
        } else {
          minv[static_cast<std::size_t>(jj)] -= delta;
        }
      }
      j0 = j1;
    } while (p[static_cast<std::size_t>(j0)] != 0);
    do {
      const int j1 = way[static_cast<std::size_t>(j0)];
      p[static_cast<std::size_t>(j0)] = p[static_cast<std::size_t>(j1)];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> assign(static_cast<std::size_t>(m), -1);
  for (int jj = 1; jj <= m; ++jj) assign[static_cast<std::size_t>(p[static_cast<std::size_t>(jj)] - 1)] = jj - 1;
  return assign;
}

}  // namespace

namespace {

/// The case with the key at x: a model parameter is set in place (the model's instantiate checks
/// its range), without deriving the model again; any other key through sim::set_value.
sim::Case case_at(const sim::Case& c, const std::string& key, double x) {
  sim::Case ck = c;
  const std::string prefix = "parameters.";
  if (key.rfind(prefix, 0) == 0 && c.setup.parameters.count(key.substr(prefix.size())) &&
      !sim::is_integer_key(c, key)) {
    ck.table["parameters"].as_table()->insert_or_assign(key.substr(prefix.size()), x);
    sim::retype(ck);
    return ck;
  }
  sim::set_value(ck, {key, sim::is_integer_key(c, key) ? format_number(std::round(x)) : format_number(x)});
  return ck;
}

std::vector<std::complex<double>> eigenvalues_of(const nlohmann::json& j) {
  std::vector<std::complex<double>> lam;
  for (const auto& e : j["eigenvalues"]) lam.emplace_back(e["re"].get<double>(), e["im"].get<double>());
  return lam;
}

}  // namespace

nlohmann::json modes_vary(const sim::Case& c, const ModesOptions& o, const VarySpec& vary) {
  if (!sim::is_numeric_key(c, vary.key))
    throw InputError("--vary " + vary.key + ": not a numeric key of the case (e.g. parameters.NAME)");
  std::unique_ptr<OutputDirectory> out;
  if (o.out_dir) out = std::make_unique<OutputDirectory>(*o.out_dir, "modes");
  const int steps = vary.count;
  std::vector<double> values(static_cast<std::size_t>(steps)), wex(static_cast<std::size_t>(steps)),
      ztol(static_cast<std::size_t>(steps));
  std::vector<std::vector<std::complex<double>>> tracks;  // [track][step]
  std::vector<std::vector<std::complex<double>>> utracks;  // undamped omega^2, paired the same way
  int dimension = -1;
  std::string first_excitation;
  Eigen::MatrixXcd vectors;  // the tracks' current eigenvectors
  std::vector<std::vector<Eigen::VectorXcd>> track_vectors;  // [track][step]
  for (int k = 0; k < steps; ++k) {
    const double x = vary.start + (vary.stop - vary.start) * k / (steps - 1);
    values[static_cast<std::size_t>(k)] = x;
    sim::Case ck = c;
    const std::string at = vary.key + " = " + format_number(x);
    nlohmann::json j;
    Linearization Lk;
    try {
      ck = case_at(c, vary.key, x);
      j = case_modes(ck, o, &Lk);
    } catch (const NumericalError& e) {
      throw NumericalError("--vary: at " + at + ": " + e.what() + "; nothing written", e.time());
    } catch (const InputError& e) {
      throw InputError("--vary: at " + at + ": " + e.what() + "; nothing written");
    }
    std::vector<std::complex<double>> lam = eigenvalues_of(j);
    ztol[static_cast<std::size_t>(k)] = j["zero_tolerance"].get<double>();
    wex[static_cast<std::size_t>(k)] = j["excitation"]["frequency_rad_s"].is_null() ? kNaN
                                                                                    : j["excitation"]["frequency_rad_s"].get<double>();
    std::vector<std::complex<double>> w2;
    for (const auto& u : j["undamped"]["frequencies"]) w2.emplace_back(u["omega2"].get<double>(), 0.0);
    if (k == 0) {
      for (const auto& w2i : w2) utracks.push_back({w2i});
    } else if (w2.size() == utracks.size()) {
      std::vector<std::complex<double>> pred;
      for (const auto& t : utracks) {
        const std::size_t s = t.size();
        pred.push_back(s >= 2 ? 2.0 * t[s - 1] - t[s - 2] : t[s - 1]);
      }
      const std::vector<int> a = pair_by_continuity(pred, w2);
      for (std::size_t i = 0; i < utracks.size(); ++i) utracks[i].push_back(w2[static_cast<std::size_t>(a[i])]);
    }
    if (k == 0) {
      first_excitation = j["excitation"]["meaning"].get<std::string>();
      dimension = static_cast<int>(lam.size());
      // Tracks in the order of |lambda|, with their eigenvectors.
      std::vector<int> order(lam.size());
      for (std::size_t m = 0; m < lam.size(); ++m) order[m] = static_cast<int>(m);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return std::abs(lam[a]) != std::abs(lam[b]) ? std::abs(lam[a]) < std::abs(lam[b]) : lam[a].imag() < lam[b].imag();
      });
      vectors = Eigen::MatrixXcd(Lk.eigenvectors.rows(), static_cast<Eigen::Index>(lam.size()));
      for (std::size_t m = 0; m < order.size(); ++m) {
        tracks.push_back({lam[static_cast<std::size_t>(order[m])]});
        vectors.col(static_cast<Eigen::Index>(m)) = Lk.eigenvectors.col(order[m]);
        track_vectors.push_back({Lk.eigenvectors.col(order[m])});
      }
      continue;
    }
    if (static_cast<int>(lam.size()) != dimension)
      throw NumericalError("--vary: at " + at + ": the tangent space has dimension " + std::to_string(lam.size()) +
                               " where it had " + std::to_string(dimension) +
                               ": the constraints change rank in the range, and the linearization does not continue "
                               "through it; nothing written",
                           0.0);
    // Predict each track's next value by linear extrapolation of its last two, then assign.
    std::vector<std::complex<double>> pred;
    std::vector<double> scales;
    for (const auto& t : tracks) {
      const std::size_t s = t.size();
      pred.push_back(s >= 2 ? 2.0 * t[s - 1] - t[s - 2] : t[s - 1]);
      scales.push_back(std::max(s >= 2 ? std::abs(t[s - 1] - t[s - 2]) : 0.0, 1e-3 * std::abs(t[s - 1])));
    }
    const std::vector<int> a = pair_by_continuity(pred, lam, vectors, Lk.eigenvectors, scales);
    Eigen::MatrixXcd next_vectors(vectors.rows(), vectors.cols());
    for (std::size_t i = 0; i < tracks.size(); ++i) {
      tracks[i].push_back(lam[static_cast<std::size_t>(a[i])]);
      next_vectors.col(static_cast<Eigen::Index>(i)) = Lk.eigenvectors.col(a[i]);
      track_vectors[i].push_back(Lk.eigenvectors.col(a[i]));
    }
    vectors = next_vectors;
  }
  nlohmann::json j;
  j["case"] = c.name;
  j["model"] = c.model->name();
  j["key"] = vary.key;
  j["values"] = values;
  j["excitation"] = first_excitation;
  nlohmann::json w = nlohmann::json::array();
  for (double x : wex) w.push_back(num(x));
  j["excitation_frequency_rad_s"] = w;
  j["pairing"] = "by continuity: at each step the eigenvalues are assigned to the tracks by the least total cost "
                 "|predicted - lambda| (2 - |u.v|) (Hungarian method), each track's value predicted by linear "
                 "extrapolation of its last two steps, u.v the overlap of the unit eigenvectors in (dq, dq_d): "
                 "where eigenvalues come close the mode shapes decide";
  nlohmann::json tr = nlohmann::json::array(), crossings = nlohmann::json::array();
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    std::vector<double> re, im;
    for (const auto& l : tracks[i]) {
      re.push_back(l.real());
      im.push_back(l.imag());
    }
    tr.push_back({{"track", i + 1}, {"re", re}, {"im", im}});
    for (int k = 1; k < steps; ++k) {
      const std::size_t k0 = static_cast<std::size_t>(k - 1), k1 = static_cast<std::size_t>(k);
      const double a = re[k0], b = re[k1];
      // A zero eigenvalue's rounding noise (|Re| within the zero tolerance) is no crossing.
      const double z = std::max(ztol[k0], ztol[k1]);
      if (!((a < -z && b > z) || (a > z && b < -z))) continue;
      const double x0 = values[k0], x1 = values[k1];
      // The root of the track's real part between the two steps: the Illinois (modified
      // regula falsi) method on Re of the eigenvalue nearest the track's interpolated value.
      const std::complex<double> l0 = tracks[i][k0], l1 = tracks[i][k1];
      int evaluations = 0;
      // The eigenvalue of the track at xv: least |λ − interpolated| + |l1 − l0| (1 − overlap with
      // the track's eigenvector at the nearer step), as the pairing chooses.
      auto re_at = [&](double xv, std::complex<double>& lam_out) {
        const double s = (xv - x0) / (x1 - x0);
        const std::complex<double> guess = l0 + s * (l1 - l0);
        const Eigen::VectorXcd& u = track_vectors[i][s < 0.5 ? k0 : k1];
        Linearization Lx;
        const auto lam = eigenvalues_of(case_modes(case_at(c, vary.key, xv), o, &Lx));
        ++evaluations;
        std::size_t best = 0;
        double best_cost = std::numeric_limits<double>::infinity();
        for (std::size_t m = 0; m < lam.size(); ++m) {
          const double ov = std::min(1.0, std::abs(u.dot(Lx.eigenvectors.col(static_cast<Eigen::Index>(m)))));
          const double cost = std::abs(lam[m] - guess) + std::abs(l1 - l0) * (1.0 - ov);
          if (cost < best_cost) {
            best_cost = cost;
            best = m;
          }
        }
        lam_out = lam[best];
        // Where the track meets other eigenvalues (a real eigenvalue crossing 0 through a cluster
        // of zero eigenvalues: a defective multiple root, each member ill-conditioned), the sum
        // of the cluster around the interpolated value is well-conditioned: the zeros add
        // nothing to it, and it is the track's real part.
        const double rho = 0.25 * std::abs(l1 - l0);
        double sum = 0;
        int members = 0;
        for (const auto& l : lam)
          if (std::abs(l - guess) <= rho) {
            sum += l.real();
            ++members;
          }
        return members > 1 ? sum : lam[best].real();
      };
      double xa = x0, xb = x1, fa = a, fb = b, root = x0 + (x1 - x0) * (-a) / (b - a);
      std::complex<double> at = l1;
      int side = 0;
      try {
        for (int it = 0; it < 60; ++it) {
          const double xm = xb - fb * (xb - xa) / (fb - fa);
          std::complex<double> lm;
          const double fm = re_at(xm, lm);
          root = xm;
          at = lm;
          if (fm == 0 || std::abs(xb - xa) <= 1e-13 * std::max(1.0, std::abs(xm))) break;
          if ((fm > 0) == (fb > 0)) {
            xb = xm;
            fb = fm;
            if (side == -1) fa /= 2;
            side = -1;
          } else {
            xa = xm;
            fa = fm;
            if (side == 1) fb /= 2;
            side = 1;
          }
          if (std::abs(fm) <= 1e-15 * std::max(1.0, std::abs(lm))) break;
        }
      } catch (const Error&) {
        // The linearization failed between two steps that had one: keep the interpolated value.
      }
      crossings.push_back({{"track", i + 1},
                           {"value", root},
                           {"interpolated", x0 + (x1 - x0) * (-a) / (b - a)},
                           {"evaluations", evaluations},
                           {"direction", b > 0 ? "becomes unstable" : "becomes stable"},
                           {"im", at.imag()}});
    }
  }
  j["tracks"] = tr;
  nlohmann::json ut = nlohmann::json::array();
  for (std::size_t i = 0; i < utracks.size(); ++i) {
    nlohmann::json om = nlohmann::json::array();
    for (const auto& x : utracks[i]) om.push_back(num(x.real() >= 0 ? std::sqrt(x.real()) : kNaN));
    ut.push_back({{"track", i + 1}, {"omega_rad_s", om}});
  }
  j["undamped_tracks"] = ut;
  j["undamped_note"] = "undamped frequencies (damping and gyroscopic terms dropped) per step, paired by continuity "
                       "of omega^2; null where omega^2 < 0 (statically unstable)";
  j["stability_crossings"] = crossings;
  j["crossing_note"] = "where a track's real part changes sign between two steps (beyond the zero tolerance): "
                       "'value' is the root of the real part (Illinois method on the eigenvalue nearest the "
                       "track, to 1e-13 relative in the key), 'interpolated' the linear interpolation";
  if (out) {
    std::ostringstream csv;
    csv << vary.key << ",excitation_frequency_rad_s";
    for (std::size_t i = 0; i < tracks.size(); ++i) csv << ",re_" << i + 1 << ",im_" << i + 1;
    for (std::size_t i = 0; i < utracks.size(); ++i) csv << ",undamped_" << i + 1;
    csv << "\n";
    for (int k = 0; k < steps; ++k) {
      csv << format_number(values[static_cast<std::size_t>(k)]) << ","
          << (std::isfinite(wex[static_cast<std::size_t>(k)]) ? format_number(wex[static_cast<std::size_t>(k)]) : "");
      for (const auto& t : tracks)
        csv << "," << format_number(t[static_cast<std::size_t>(k)].real()) << ","
            << format_number(t[static_cast<std::size_t>(k)].imag());
      for (const auto& t : utracks) {
        const double w2 = t[static_cast<std::size_t>(k)].real();
        csv << "," << (w2 >= 0 ? format_number(std::sqrt(w2)) : std::string());
      }
      csv << "\n";
    }
    out->write("modes_vary.csv", csv.str());
    out->write("modes_vary.json", j.dump(2) + "\n");
    out->commit();
  }
  return j;
}

std::string vary_report(const nlohmann::json& j) {
  std::ostringstream os;
  const auto& values = j["values"];
  os << "pcsim modes --vary: case '" << j["case"].get<std::string>() << "', " << j["tracks"].size()
     << " eigenvalues traced over " << j["key"].get<std::string>() << " = " << f(values.front().get<double>())
     << " .. " << f(values.back().get<double>()) << " (" << values.size() << " steps), paired by continuity\n";
  os << "  excitation " << j["excitation"].get<std::string>() << "\n";
  os << "  track: eigenvalue at the first and the last step\n";
  for (const auto& t : j["tracks"]) {
    const auto& re = t["re"];
    const auto& im = t["im"];
    if (im.front().get<double>() < 0 && im.back().get<double>() < 0) continue;  // the conjugate of another track
    os << "    " << t["track"].get<int>() << ": " << f(re.front().get<double>(), 5) << (im.front().get<double>() < 0 ? " - " : " + ")
       << f(std::abs(im.front().get<double>()), 5) << "i  ->  " << f(re.back().get<double>(), 5)
       << (im.back().get<double>() < 0 ? " - " : " + ") << f(std::abs(im.back().get<double>()), 5) << "i\n";
  }
  if (!j["undamped_tracks"].empty()) {
    os << "  undamped frequencies (rad/s), first -> last step:";
    for (const auto& t : j["undamped_tracks"]) {
      const auto& w = t["omega_rad_s"];
      auto v = [](const nlohmann::json& x) { return x.is_null() ? std::string("unstable") : f(x.get<double>(), 5); };
      os << "  " << v(w.front()) << " -> " << v(w.back());
    }
    os << "\n";
  }
  if (j["stability_crossings"].empty()) os << "  no real part changes sign in the range\n";
  for (const auto& x : j["stability_crossings"]) if (x["im"].get<double>() >= 0)
    os << "  track " << x["track"].get<int>() << " " << x["direction"].get<std::string>() << " at "
       << j["key"].get<std::string>() << " ~ " << f(x["value"].get<double>(), 6) << " (Im = "
       << f(x["im"].get<double>(), 4) << ")\n";
  return os.str();
}

}  // namespace pcsim::modes
