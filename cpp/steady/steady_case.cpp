// `pcsim steady` for a case (see steady_case.hpp).
#include "steady/steady_case.hpp"
#include "common/eigen_instances.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <Eigen/SVD>

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "mech/projection.hpp"
#include "sim/client.hpp"
#include "sim/run.hpp"
#include "steady/forced_model.hpp"
#include "steady/own_reaction_model.hpp"

namespace pcsim::steady {

namespace {

std::string where(const sim::Case& c) { return input_location(c.source); }

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

ShootingOptions shooting_options(const sim::Setup& s, OdeMethod method) {
  ShootingOptions o;
  o.method = method;
  o.kernel = s.kernel;
  o.rtol = s.rtol;
  o.atol = s.atol;
  o.max_steps = s.max_steps;
  return o;
}

CaseOrbit::CaseOrbit(const sim::Case& c, int periods, std::string key)
    : case_(c), setup_(c.setup), periods_(periods), key_(std::move(key)),
      base_value_(std::numeric_limits<double>::quiet_NaN()) {
  const std::string w = where(c);
  if (periods_ < 1) throw InputError("--periods: expected an integer >= 1, got " + std::to_string(periods_));
  if (!std::isfinite(setup_.period) || !(setup_.period > 0))
    throw InputError(w + ": the " + c.model->origin() +
                     " declares no excitation period, which a periodic steady state needs (a "
                     "model file declares it in [model], e.g. period = \"2*pi/omega\")");
  // The orbit is the smooth system's, with every contact held; its verdicts say whether it is
  // physical. A steady state of a switching system (a hybrid periodic orbit through lift-offs
  // and landings) is a different problem that shooting here does not solve: refuse it rather
  // than report the smooth orbit under a switching heading.
  if (setup_.contact.switching)
    throw InputError(w + ": key 'contact.switching': expected false for pcsim steady and pcsim "
                     "response (the periodic orbit is the smooth system's with its contacts "
                     "held; its verdicts say whether a contact would open). For the motion "
                     "after a contact opens, run the case with pcsim run and a long "
                     "solver.t_end");
  if (!key_.empty()) {
    const auto dot = key_.find('.');
    const std::string section = key_.substr(0, dot), name = dot == std::string::npos ? "" : key_.substr(dot + 1);
    if (!sim::is_numeric_key(c, key_))
      throw InputError("--vary " + key_ + ": not a numeric key of the case");
    if (section == "parameters") {
      kind_ = KeyKind::parameter;
      name_ = name;
      base_value_ = setup_.parameters.at(name);
    } else if (section == "initial") {
      kind_ = KeyKind::held_value;
      name_ = name;
      const auto v = c.table["initial"][name].value<double>();
      base_value_ = v ? *v : 0.0;
    } else {
      throw InputError("--vary " + key_ + ": pcsim response varies a model parameter "
                       "(parameters.NAME) or an initial value (initial.NAME: the held value of a "
                       "slow coordinate, or the constant of a from_initial constraint)");
    }
  }
  const auto model = model_at(base_value_);
  if (!model->has_tangents())
    throw InputError(w + ": the " + c.model->origin() +
                     " instance has no exact tangents, which the monodromy matrix needs: only "
                     "models from model files have them (the sieve's default model is one; its "
                     "C++ variants are not)");
  std::string msg;
  if (mech::resolve_constraints(*model, setup_.active, active_, msg) != mech::ModelIssue::none)
    throw InputError(w + ": " + msg);
  // Every shooting integration runs over the orbit period kT on the case's step budget: a
  // period the budget cannot cover (omega = 1e-9: kT = 6e9 s) is refused before any work.
  {
    std::string keys;
    for (const auto& [name, value] : setup_.parameters) {
      sim::ParameterValues p = setup_.parameters;
      p[name] = value * (1 + 1e-6) + 1e-9;
      if (!(c.model->period(p) == setup_.period)) keys += (keys.empty() ? "parameters." : ", parameters.") + name;
    }
    sim::check_step_budget(c, setup_, *model, periods_ * setup_.period,
                           "the orbit period " + (periods_ == 1 ? std::string() : std::to_string(periods_) + " x ") +
                               format_significant(setup_.period, 6) + " s" +
                               (keys.empty() ? std::string() : " (set by " + keys + ")") +
                               ", which every shooting integration covers");
  }
  // The slow coordinates: held at their initial value, unless the active constraints already
  // fix them (e.g. a constraint added to hold one rigidly): holding it twice is singular.
  const int n = model->n();
  std::vector<int> hol;
  for (int i : active_)
    if (model->constraints()[i].kind == mech::ConstraintKind::holonomic) hol.push_back(i);
  Eigen::MatrixXd g(hol.size(), n), gw(hol.size(), n);
  Eigen::VectorXd g0(hol.size()), gamma(hol.size());
  if (!hol.empty()) model->constraint_rows(hol, 0.0, setup_.q0, setup_.qd0, g, g0, gamma);
  auto rank = [](const Eigen::MatrixXd& A) {
    if (A.rows() == 0) return 0;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A);
    const Eigen::VectorXd s = svd.singularValues();
    int r = 0;
    for (int i = 0; i < s.size(); ++i) r += s[i] > 1e-10 * std::max(1.0, s[0]);
    return r;
  };
  const int r0 = rank(g);
  for (const auto& sname : c.model->slow_coordinates()) {
    const int i = c.model->coordinate_index(sname);
    if (i < 0) continue;
    Eigen::MatrixXd ge(g.rows() + 1, n);
    ge.topRows(g.rows()) = g;
    ge.row(g.rows()).setZero();
    ge(g.rows(), i) = 1.0;
    if (rank(ge) == r0) {
      fixed_slow_.push_back(sname);
      continue;
    }
    held_.push_back(sname);
    slow_.push_back(i);
  }
  // Constraints the case added that hold a slow coordinate rigidly: their rows involve one.
  if (const toml::table* added = c.table["constraints"]["added"].as_table()) {
    for (const auto& [k, v] : *added) {
      const int ci = model->constraint_index(std::string(k.str()));
      if (ci < 0 || std::find(active_.begin(), active_.end(), ci) == active_.end()) continue;
      Eigen::MatrixXd gr(1, n);
      Eigen::VectorXd g0r(1), gar(1);
      model->constraint_rows({ci}, 0.0, setup_.q0, setup_.qd0, gr, g0r, gar);
      for (const auto& sname : c.model->slow_coordinates()) {
        const int i = c.model->coordinate_index(sname);
        if (i >= 0 && gr(0, i) != 0.0) {
          holding_constraints_.push_back(ci);
          break;
        }
      }
    }
  }
  if (kind_ == KeyKind::held_value) {
    // Which held value (if any) the key moves; a key that moves none may still move the
    // constant of a from_initial constraint, which the continuation follows as well.
    const Eigen::VectorXd a = q0_at(base_value_), b = q0_at(base_value_ + 1.0);
    for (std::size_t k = 0; k < slow_.size(); ++k)
      if (a[slow_[k]] != b[slow_[k]]) held_index_ = static_cast<int>(k);
  }
  if (kind_ != KeyKind::none) check_key_moves_the_orbit();
}

// A varied key must be able to change the periodic orbit: the orbit of a periodic steady
// state forgets its initial state (Newton finds the same orbit from any start), so an initial
// value moves the response only as the held value of a slow coordinate or the constant of a
// from_initial constraint; a parameter only if it enters the model's equations, outputs or
// excitation period. A key that moves none of these would draw a flat curve: refused.
void CaseOrbit::check_key_moves_the_orbit() const {
  const double a = base_value_;
  const double b = base_value_ != 0 ? base_value_ * (1 + 1e-3) + 1e-3 : 0.5;
  bool moves = held_index_ >= 0;
  // A model with a client (the sieve) may use a parameter in its verdicts only (the sieve's
  // friction coefficient f in the rolling margin): the response's columns then move although
  // the orbit does not, so its parameters are all accepted.
  if (kind_ == KeyKind::parameter && case_.client) moves = true;
  if (!moves) {
    std::shared_ptr<const mech::Model> ma, mb;
    try {
      ma = model_at(a);
      mb = model_at(b);
    } catch (const InputError&) {
      return;  // b outside the key's range: cannot tell, the continuation will say
    }
    const int n = ma->n();
    const double p_a = case_.model->period(parameters_at(a)), p_b = case_.model->period(parameters_at(b));
    moves = !(p_a == p_b);
    const int s = static_cast<int>(ma->constraints().size());
    std::vector<int> all(static_cast<std::size_t>(s));
    for (int i = 0; i < s; ++i) all[static_cast<std::size_t>(i)] = i;
    // Two states (the case's start and a generic one) at two times: every term the orbit is
    // made of (M, h, Q, the constraint rows and positions, the outputs) compared.
    for (int trial = 0; trial < 2 && !moves; ++trial) {
      Eigen::VectorXd q = setup_.q0, qd = setup_.qd0;
      const double t = trial == 0 ? 0.0 : 0.3 * (std::isfinite(p_a) ? p_a : 1.0);
      if (trial == 1)
        for (int i = 0; i < n; ++i) {
          q[i] += 0.01 * (i + 1) * (1 + std::abs(q[i]));
          qd[i] += 0.02 * (i + 2) * (1 + std::abs(qd[i]));
        }
      Eigen::MatrixXd Ma(n, n), Mb(n, n), ga(s, n), gb(s, n);
      Eigen::VectorXd ha(n), hb(n), Qa(n), Qb(n), g0a(s), g0b(s), gaa(s), gab(s);
      ma->kinetic_terms(t, q, qd, Ma, ha);
      mb->kinetic_terms(t, q, qd, Mb, hb);
      ma->forces(t, q, qd, Qa);
      mb->forces(t, q, qd, Qb);
      auto differ = [](const auto& x, const auto& y) {
        for (Eigen::Index i = 0; i < x.size(); ++i)
          if (!(x.data()[i] == y.data()[i]) && !(std::isnan(x.data()[i]) && std::isnan(y.data()[i])))
            return true;
        return false;
      };
      moves = differ(Ma, Mb) || differ(ha, hb) || differ(Qa, Qb);
      if (!moves && s > 0) {
        ma->constraint_rows(all, t, q, qd, ga, g0a, gaa);
        mb->constraint_rows(all, t, q, qd, gb, g0b, gab);
        moves = differ(ga, gb) || differ(g0a, g0b) || differ(gaa, gab);
        for (int i = 0; i < s && !moves; ++i)
          if (ma->constraints()[i].kind == mech::ConstraintKind::holonomic) {
            const double ra = ma->position_residual(i, t, q), rb = mb->position_residual(i, t, q);
            moves = !(ra == rb) && !(std::isnan(ra) && std::isnan(rb));
          }
      }
      if (!moves && !ma->derived_names().empty()) {
        const Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
        Eigen::VectorXd oa(ma->derived_names().size()), ob(mb->derived_names().size());
        ma->derived(t, q, qd, z, z, oa);
        mb->derived(t, q, qd, z, z, ob);
        moves = differ(oa, ob);
      }
    }
  }
  if (moves) return;
  if (kind_ == KeyKind::held_value)
    throw InputError(
        "--vary " + key_ + ": an initial value cannot change a periodic steady state (Newton "
        "finds the same orbit from any start, so the response would be a flat curve); pcsim "
        "response varies initial.NAME only where it is the held value of a slow coordinate" +
        std::string(c_slow_names().empty() ? " (the " + case_.model->origin() + " declares none)"
                                           : " (" + c_slow_names() + ")") +
        " or the constant of a from_initial constraint. Vary a model parameter "
        "(parameters.NAME) instead");
  throw InputError("--vary " + key_ + ": the parameter does not enter the " +
                   case_.model->origin() + "'s equations, outputs or excitation period, so the "
                   "periodic orbit cannot depend on it (the response would be a flat curve)");
}

std::string CaseOrbit::c_slow_names() const {
  std::string out;
  for (const auto& h : held_) out += (out.empty() ? "initial." : ", initial.") + h;
  return out;
}

sim::ParameterValues CaseOrbit::parameters_at(double value) const {
  sim::ParameterValues p = setup_.parameters;
  if (kind_ == KeyKind::parameter) p[name_] = value;
  return p;
}

Eigen::VectorXd CaseOrbit::q0_at(double value) const {
  if (kind_ != KeyKind::held_value) return setup_.q0;
  sim::Case c = case_;
  c.table["initial"].as_table()->insert_or_assign(name_, value);
  sim::retype(c);
  return c.setup.q0;
}

std::shared_ptr<const mech::Model> CaseOrbit::model_at(double value) const {
  return case_.model->instantiate(parameters_at(value), q0_at(value), 0.0, case_.table, "");
}

OrbitProblem CaseOrbit::problem(double value) const {
  OrbitProblem p;
  p.model = model_at(value);
  p.active = active_;
  p.period = case_.model->period(parameters_at(value));
  p.periods = periods_;
  p.slow = slow_;
  const Eigen::VectorXd q0 = q0_at(value);
  p.hold.resize(slow_.size());
  for (std::size_t k = 0; k < slow_.size(); ++k) p.hold[k] = q0[slow_[k]];
  return p;
}

ParameterDerivative CaseOrbit::derivative(double value) const {
  ParameterDerivative d;
  const double h = 1e-5 * std::max(std::abs(value), 1e-3);
  double lo = value - h, hi = value + h;
  d.model_plus = model_at(hi);
  try {
    d.model_minus = model_at(lo);
  } catch (const InputError&) {  // value - h is outside the key's range: a forward difference
    lo = value;
    d.model_minus = model_at(lo);
  }
  d.h = (hi - lo) / 2;
  d.dperiod = (case_.model->period(parameters_at(hi)) - case_.model->period(parameters_at(lo))) / (hi - lo);
  const Eigen::VectorXd qa = q0_at(lo), qb = q0_at(hi);
  d.dhold.resize(slow_.size());
  for (std::size_t k = 0; k < slow_.size(); ++k) d.dhold[k] = (qb[slow_[k]] - qa[slow_[k]]) / (hi - lo);
  return d;
}

OrbitPoint CaseOrbit::guess() const {
  const int n = static_cast<int>(setup_.q0.size());
  OrbitPoint x;
  x.y.resize(2 * n);
  x.H = Eigen::VectorXd::Zero(slow_.size());
  if (setup_.equilibrium_start) {
    const auto model = model_at(base_value_);
    const mech::EquilibriumResult e = sim::case_equilibrium(case_, setup_, *model);
    x.y.head(n) = e.q;
    x.y.tail(n).setZero();
    const auto all = case_.model->slow_coordinates();
    for (std::size_t k = 0; k < held_.size(); ++k)
      for (std::size_t a = 0; a < all.size(); ++a)
        if (all[a] == held_[k] && static_cast<Eigen::Index>(a) < e.holding_force.size())
          x.H[k] = e.holding_force[a];
  } else {
    x.y.head(n) = setup_.q0;
    x.y.tail(n) = setup_.qd0;
  }
  return x;
}

sim::RunResult period_summary(const CaseOrbit& orbit, const OrbitResult& result,
                              OutputDirectory* dir) {
  sim::Case c = orbit.source_case();
  const OrbitProblem p = orbit.problem();
  const double kT = p.periods * p.period;
  toml::table& solver = *c.table["solver"].as_table();
  solver.insert_or_assign("t_end", kT);
  toml::table& output = *c.table["output"].as_table();
  output.erase("summary_time");
  // At least 200 time-series rows per orbit period (a case's dt is often set for long runs).
  if (c.setup.dt > kT / 200) output.insert_or_assign("dt", kT / 200);
  output.insert_or_assign("summary_periods", int64_t{p.periods});
  sim::retype(c);
  const int n = static_cast<int>(result.point.y.size() / 2);
  sim::RunOptions ro;
  ro.start = std::make_pair(Eigen::VectorXd(result.point.y.head(n)), Eigen::VectorXd(result.point.y.tail(n)));
  const std::vector<int> slow = p.slow;
  const Eigen::VectorXd H = result.point.H;
  const std::vector<int> active = orbit.active(), holding = orbit.holding_constraints();
  ro.wrap_model = [slow, H, active, holding](std::shared_ptr<const mech::Model> m) {
    m = with_forces(std::move(m), slow, H);
    if (!holding.empty()) m = std::make_shared<const OwnReactionModel>(std::move(m), active, holding);
    return m;
  };
  ro.directory = dir;
  return sim::run_case(c, ro);
}

nlohmann::json orbit_json(const CaseOrbit& orbit, const OrbitResult& r, const sim::RunResult* summary) {
  const sim::Case& c = orbit.source_case();
  const OrbitProblem p = orbit.problem();
  const auto& coords = c.model->coordinates();
  const int n = static_cast<int>(coords.size());
  nlohmann::json j;
  j["case"] = c.name;
  j["model"] = c.model->name();
  j["period"] = p.period;
  j["periods"] = p.periods;
  j["orbit_period"] = p.periods * p.period;
  j["t0"] = p.t0;
  j["start"] = orbit.setup().equilibrium_start ? "equilibrium" : "state";
  nlohmann::json q = nlohmann::json::object(), qd = nlohmann::json::object();
  for (int i = 0; i < n; ++i) {
    q[coords[i]] = r.point.y[i];
    qd[coords[i] + "_d"] = r.point.y[n + i];
  }
  j["state"] = {{"q", q}, {"qd", qd}};
  nlohmann::json slow = nlohmann::json::object();
  for (std::size_t k = 0; k < orbit.held().size(); ++k) {
    nlohmann::json s;
    s["held_mean"] = p.hold[k];
    s["holding_force"] = r.point.H[k];
    s["drift_acceleration"] = num(k < static_cast<std::size_t>(r.drift_acceleration.size())
                                      ? r.drift_acceleration[k]
                                      : std::numeric_limits<double>::quiet_NaN());
    if (r.last.C_mean.rows() == static_cast<Eigen::Index>(orbit.held().size()))
      s["mean_inverse_mass"] = r.last.C_mean(k, k);
    slow[orbit.held()[k]] = s;
  }
  j["slow"] = slow;
  j["slow_fixed_by_constraints"] = orbit.fixed_slow();
  if (!orbit.holding_constraints().empty()) {
    nlohmann::json names = nlohmann::json::array();
    const auto model = orbit.problem().model;
    for (int i : orbit.holding_constraints()) names.push_back(model->constraints()[i].name);
    j["outputs_without_the_reactions_of"] = names;
  }
  nlohmann::json mu = nlohmann::json::array();
  for (const auto& m : r.floquet.multipliers)
    mu.push_back({{"re", m.value.real()}, {"im", m.value.imag()}, {"modulus", m.modulus}, {"slow", m.slow}});
  j["floquet"] = {{"multipliers", mu},
                  {"max_modulus", r.floquet.max_modulus},
                  {"stable", r.floquet.stable},
                  {"dimension", static_cast<int>(r.floquet.multipliers.size())}};
  nlohmann::json hist = nlohmann::json::array();
  int linearizations = 0;
  for (const auto& h : r.history) {
    nlohmann::json e = {{"iteration", h.iteration},
                        {"residual", h.residual},
                        {"residual_max", h.residual_max},
                        {"steps", h.steps}};
    if (h.check) {
      e["check"] = "the residual of the final point (no linearization there)";
    } else {
      e["correction"] = h.correction;
      e["damping"] = h.damping;
      ++linearizations;
    }
    hist.push_back(e);
  }
  j["newton"] = {{"converged", r.converged},
                 {"iterations", linearizations},
                 {"residual", r.residual},
                 {"residual_max", r.residual_max},
                 {"correction", r.correction},
                 {"note", r.message},
                 {"transient_periods", r.transient_periods},
                 {"norm", "weighted RMS, weights 1/(atol + rtol |y_i|): 1 = the integration tolerance"},
                 {"history", hist}};
  j["shooting"] = {{"integrations", r.integrations},
                   {"steps", r.steps},
                   {"f_evals", r.f_evals},
                   {"methods_used", r.used_explicit && r.used_radau ? "explicit, radau"
                                    : r.used_radau                  ? "radau"
                                                                    : "explicit"}};
  if (summary) {
    // The periodicity of the summary run (the case's own integrator from the periodic state).
    double gap = 0;
    for (int i = 0; i < n; ++i) {
      gap = std::max(gap, std::abs(summary->q_end.at(coords[i]) - r.point.y[i]));
      gap = std::max(gap, std::abs(summary->qd_end.at(coords[i] + "_d") - r.point.y[n + i]));
    }
    j["periodicity_check"] = gap;
    j["summary"] = sim::to_json(*summary);
  }
  return j;
}

nlohmann::json steady_case(const sim::Case& c, const SteadyOptions& options) {
  CaseOrbit orbit(c, options.periods);
  std::unique_ptr<OutputDirectory> out;
  if (options.out_dir) out = std::make_unique<OutputDirectory>(*options.out_dir, "steady");
  ShootingOptions so = shooting_options(orbit.setup(), options.method);
  so.max_iterations = options.max_iterations;
  so.newton_tol = options.newton_tol;
  so.max_transient_periods = options.max_transient_periods;
  if (options.summary && out) {
    // The period's time series (at least 200 rows per orbit period): its rows are bounded as
    // pcsim run's are, before the shooting starts.
    const double kT = options.periods * orbit.setup().period;
    const double dt = std::min(orbit.setup().dt, kT / 200);
    const double rows = std::floor(kT / dt) + 2;
    if (!(rows <= sim::kMaxOutputRows))
      throw InputError(where(c) + ": key 'output.dt': expected at most " +
                       format_number(sim::kMaxOutputRows) + " time-series rows over the orbit "
                       "period " + format_significant(kT, 6) + " s, got " +
                       format_significant(rows, 3) + " rows; raise output.dt");
  }
  const auto t_start = std::chrono::steady_clock::now();
  const OrbitResult r = find_orbit(orbit.problem(), orbit.guess(), so);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (!r.converged) {
    // What was computed is kept: the Newton iterations (their residuals and corrections) and
    // the last iterate, in steady.json marked "complete": false with the reason. No period run:
    // a state that is not periodic is not a steady state.
    std::string kept;
    if (out) {
      try {
        nlohmann::json j = orbit_json(orbit, r, nullptr);
        j["complete"] = false;
        j["failure"] = {{"reason", r.message}, {"t", r.last.t_failed}};
        j["shooting"]["method"] = to_string(options.method);
        j["shooting"]["rtol"] = so.rtol;
        j["shooting"]["atol"] = so.atol;
        j["shooting"]["wall_seconds"] = wall;
        out->write("steady.json", j.dump(2) + "\n");
        out->commit();
        kept = "; wrote the Newton iterations and the last iterate to " + options.out_dir->string() +
               "/steady.json, marked \"complete\": false";
      } catch (const IoError&) {
        throw;
      } catch (const std::exception&) {
        // The record could not be assembled (e.g. no Floquet data): the failure is reported alone.
      }
    }
    throw NumericalError("case '" + c.name + "': " + r.message + kept, r.last.t_failed);
  }
  std::optional<sim::RunResult> summary;
  double wall_summary = 0;
  if (options.summary) {
    const auto t1 = std::chrono::steady_clock::now();
    summary = period_summary(orbit, r, out.get());
    wall_summary = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  nlohmann::json j = orbit_json(orbit, r, summary ? &*summary : nullptr);
  j["complete"] = true;
  j["shooting"]["method"] = to_string(options.method);
  j["shooting"]["rtol"] = so.rtol;
  j["shooting"]["atol"] = so.atol;
  j["shooting"]["wall_seconds"] = wall;
  j["shooting"]["summary_wall_seconds"] = wall_summary;
  if (out) {
    out->write("steady.json", j.dump(2) + "\n");
    out->commit();
  }
  return j;
}

std::string steady_report(const sim::Case& c, const nlohmann::json& s) {
  std::ostringstream os;
  auto f = [](double v, int d = 4) { return format_significant(v, d); };
  const int k = s["periods"].get<int>();
  os << "pcsim steady: case '" << s["case"].get<std::string>() << "' (" << c.model->origin()
     << "), periodic orbit of period " << f(s["orbit_period"].get<double>(), 6) << " s ("
     << (k == 1 ? std::string("one excitation period") : std::to_string(k) + " excitation periods")
     << ")\n";
  const auto& nw = s["newton"];
  os << "  Newton shooting from the case's " << (s["start"] == "equilibrium" ? "static equilibrium" : "initial state");
  if (nw.value("transient_periods", 0) > 0)
    os << " after " << nw["transient_periods"].get<int>() << " periods of transient integration";
  os << ": " << nw["iterations"].get<int>() << " iterations; residual "
     << f(nw["residual"].get<double>(), 3) << " of the integration tolerance (max |y(kT) - y(0)| = "
     << f(nw["residual_max"].get<double>(), 3) << "), last correction " << f(nw["correction"].get<double>(), 3)
     << "\n";
  if (!nw["note"].get<std::string>().empty()) os << "    (" << nw["note"].get<std::string>() << ")\n";
  for (auto it = s["slow"].begin(); it != s["slow"].end(); ++it) {
    const auto& v = it.value();
    os << "  slow coordinate " << it.key() << ": held at its period mean " << f(v["held_mean"].get<double>(), 6)
       << " by the constant generalized force " << f(v["holding_force"].get<double>())
       << "; let go, it drifts with the mean acceleration "
       << (v["drift_acceleration"].is_null() ? std::string("n/a") : f(v["drift_acceleration"].get<double>()))
       << "\n";
  }
  for (const auto& name : s["slow_fixed_by_constraints"])
    os << "  slow coordinate " << name.get<std::string>() << ": fixed by the active constraints (not held again)\n";
  const auto& fl = s["floquet"];
  os << "  Floquet multipliers (" << fl["dimension"].get<int>() << ", on the constraint manifold): largest |mu| = "
     << f(fl["max_modulus"].get<double>(), 6) << ": the orbit is "
     << (fl["stable"].get<bool>() ? "STABLE" : "UNSTABLE") << "\n    ";
  int count = 0;
  for (const auto& m : fl["multipliers"]) {
    if (count++ == 8) {
      os << " ...";
      break;
    }
    const double im = m["im"].get<double>();
    os << (count > 1 ? ", " : "") << f(m["re"].get<double>(), 5);
    if (im != 0) os << (im > 0 ? "+" : "-") << f(std::abs(im), 3) << "i";
    if (m["slow"].get<bool>()) os << " (slow)";
  }
  os << "\n";
  os << "  periodic state at t = 0:";
  int i = 0;
  for (auto it = s["state"]["q"].begin(); it != s["state"]["q"].end(); ++it, ++i)
    os << (i % 4 == 0 ? "\n    " : ", ") << it.key() << " = " << f(it.value().get<double>(), 6);
  os << "\n";
  const auto& sh = s["shooting"];
  os << "  shooting: " << sh["integrations"] << " orbit integrations with the variational equations ("
     << sh["methods_used"].get<std::string>() << "), " << sh["steps"] << " steps, " << sh["f_evals"]
     << " evaluations; " << f(sh["wall_seconds"].get<double>(), 3) << " s wall\n";
  if (s.contains("summary")) {
    os << "  one period of the orbit, run from the periodic state as pcsim run runs a case "
          "(periodicity check: max |y(kT) - y(0)| = "
       << f(s["periodicity_check"].get<double>(), 3) << "):\n";
    // The report of the period's run, with the period's case (its t_end and window).
    sim::Case pc = c;
    pc.table["solver"].as_table()->insert_or_assign("t_end", s["orbit_period"].get<double>());
    pc.table["output"].as_table()->erase("summary_time");
    pc.table["output"].as_table()->insert_or_assign("summary_periods", int64_t{k});
    sim::retype(pc);
    std::istringstream rep(
        sim::human_report(pc, sim::result_from_json(s["summary"], sim::timeseries_columns(pc))));
    std::string line;
    while (std::getline(rep, line)) os << "  | " << line << "\n";
  }
  return os.str();
}

}  // namespace pcsim::steady
