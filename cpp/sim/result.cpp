// summary.json from the typed run result and back (result.hpp).
#include "sim/result.hpp"

#include <stdexcept>

namespace pcsim::sim {

namespace {

nlohmann::json null_if_nan(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

double nan_if_null(const nlohmann::json& v) {
  return v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
}

nlohmann::json object_of(const std::map<std::string, double>& m) {
  nlohmann::json o = nlohmann::json::object();
  for (const auto& [k, v] : m) o[k] = v;
  return o;
}

std::map<std::string, double> map_of(const nlohmann::json& o) {
  std::map<std::string, double> m;
  for (const auto& [k, v] : o.items()) m[k] = v.get<double>();
  return m;
}

/// The keys to_json writes from the generic fields (the others of a summary are a client's).
const char* const kGenericKeys[] = {
    "case", "model", "model_variant", "kernel", "form", "method", "methods_used", "t_end",
    "window", "window_clipped", "summary_periods", "period", "summary_time", "stats", "q_end",
    "qd_end", "extremes", "constraint_residual_max", "constraints", "parameters", "output_dt",
    "initial_correction", "initial_state", "accuracy", "complete", "switching", "rank", "stopped",
    "failure", "t_reached"};

}  // namespace

const ColumnExtremes& RunResult::extreme(const std::string& column) const {
  const auto it = extremes.find(column);
  if (it == extremes.end())
    throw std::out_of_range("the run of case '" + case_name + "' has no column '" + column + "'");
  return it->second;
}

namespace {

/// The scalar at a dotted path below `j`, or null.
nlohmann::json scalar_at(const nlohmann::json& j, const std::string& dotted) {
  const nlohmann::json* cur = &j;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', start);
    const std::string part = dotted.substr(start, dot == std::string::npos ? dot : dot - start);
    if (cur->is_array() && !part.empty() &&
        part.find_first_not_of("0123456789") == std::string::npos && part.size() < 10 &&
        std::stoul(part) < cur->size()) {
      cur = &(*cur)[std::stoul(part)];
    } else if (cur->is_object() && cur->contains(part)) {
      cur = &(*cur)[part];
    } else {
      return nullptr;
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return cur->is_primitive() ? *cur : nlohmann::json(nullptr);
}

/// The number at `m[key]`, or null.
nlohmann::json number_in(const std::map<std::string, double>& m, const std::string& key) {
  const auto it = m.find(key);
  return it == m.end() ? nlohmann::json(nullptr) : null_if_nan(it->second);
}

}  // namespace

nlohmann::json RunResult::value(const std::string& dotted) const {
  // The client's keys first: they replace generic ones in summary.json.
  const std::string top = dotted.substr(0, dotted.find('.'));
  if (additions.contains(top)) return scalar_at(additions, dotted);
  const std::string rest = top.size() < dotted.size() ? dotted.substr(top.size() + 1) : "";
  if (top == "extremes") {
    const auto dot = rest.rfind('.');
    if (dot == std::string::npos) return nullptr;
    const auto it = extremes.find(rest.substr(0, dot));
    if (it == extremes.end()) return nullptr;
    const std::string part = rest.substr(dot + 1);
    const ColumnExtremes& e = it->second;
    if (part == "min") return null_if_nan(e.min);
    if (part == "max") return null_if_nan(e.max);
    if (part == "amplitude") return null_if_nan(e.amplitude());
    return nullptr;
  }
  if (top == "q_end") return number_in(q_end, rest);
  if (top == "qd_end") return number_in(qd_end, rest);
  if (top == "parameters") return number_in(parameters, rest);
  if (top == "stats") {
    if (rest == "wall_seconds") return stats.wall_seconds;
    const std::pair<const char*, long> counts[] = {
        {"steps", stats.steps},         {"accepted", stats.accepted},
        {"rejected", stats.rejected},   {"f_evals", stats.f_evals},
        {"jacobians", stats.jacobians}, {"lu_decompositions", stats.lu_decompositions}};
    for (const auto& [name, v] : counts)
      if (rest == name) return v;
    return nullptr;
  }
  if (dotted == "constraint_residual_max") return null_if_nan(constraint_residual_max);
  if (dotted == "window_clipped") return window_clipped;
  if (dotted == "complete") return complete;
  if (dotted == "t_end") return null_if_nan(t_end);
  if (top == "switching") return scalar_at(switching, rest);
  return scalar_at(to_json(*this), dotted);  // the rest: rarely asked for
}

nlohmann::json to_json(const RunResult& r) {
  nlohmann::json j;
  j["case"] = r.case_name;
  j["model"] = r.model;
  if (!r.model_variant.empty()) j["model_variant"] = r.model_variant;
  j["kernel"] = r.kernel;
  j["form"] = r.form;
  j["method"] = r.method;
  j["methods_used"] = r.methods_used;
  j["t_end"] = r.t_end;
  j["window"] = {r.window_start, r.window_end};
  j["window_clipped"] = r.window_clipped;
  if (r.summary_periods > 0) {
    j["summary_periods"] = r.summary_periods;
    j["period"] = r.period;
  } else {
    j["summary_time"] = r.summary_time;
  }
  j["stats"] = {{"steps", r.stats.steps},
                {"accepted", r.stats.accepted},
                {"rejected", r.stats.rejected},
                {"f_evals", r.stats.f_evals},
                {"jacobians", r.stats.jacobians},
                {"lu_decompositions", r.stats.lu_decompositions},
                {"wall_seconds", r.stats.wall_seconds}};
  j["q_end"] = object_of(r.q_end);
  j["qd_end"] = object_of(r.qd_end);
  nlohmann::json ex = nlohmann::json::object();
  for (const auto& [name, e] : r.extremes)
    ex[name] = {{"min", null_if_nan(e.min)},
                {"max", null_if_nan(e.max)},
                {"amplitude", null_if_nan(e.amplitude())}};
  j["extremes"] = ex;
  j["constraint_residual_max"] = r.constraint_residual_max;
  j["constraints"] = r.constraints;
  j["parameters"] = object_of(r.parameters);
  j["output_dt"] = r.output_dt;
  j["initial_correction"] = {{"position", r.initial_correction_position},
                             {"velocity", r.initial_correction_velocity}};
  if (r.initial_state)
    j["initial_state"] = {{"from", "equilibrium"},
                          {"q", object_of(r.initial_state->q)},
                          {"force_imbalance", r.initial_state->force_imbalance},
                          {"holding_forces", object_of(r.initial_state->holding_forces)}};
  j["accuracy"] = {{"reliable", r.accuracy.reliable},
                   {"rtol", r.accuracy.rtol},
                   {"atol", r.accuracy.atol}};
  if (!r.accuracy.reliable) j["accuracy"]["reason"] = r.accuracy.reason;
  j["complete"] = r.complete;
  if (!r.switching.is_null()) j["switching"] = r.switching;
  if (!r.rank.is_null()) j["rank"] = r.rank;
  for (const auto& [k, v] : r.additions.items()) j[k] = v;
  if (r.stopped) {
    j["stopped"] = {{"t", r.stopped->t}, {"reason", r.stopped->reason}};
    j["t_reached"] = r.t_reached;
  } else if (r.failure) {
    j["failure"] = {{"t", r.failure->t}, {"status", r.failure->status}, {"reason", r.failure->reason}};
    j["t_reached"] = r.t_reached;
  }
  return j;
}

RunResult result_from_json(const nlohmann::json& s, std::vector<std::string> columns) {
  RunResult r;
  r.case_name = s.at("case").get<std::string>();
  r.model = s.at("model").get<std::string>();
  r.model_variant = s.value("model_variant", std::string());
  r.kernel = s.at("kernel").get<std::string>();
  r.form = s.at("form").get<std::string>();
  r.method = s.at("method").get<std::string>();
  r.methods_used = s.at("methods_used").get<std::string>();
  r.t_end = s.at("t_end").get<double>();
  r.window_start = s.at("window").at(0).get<double>();
  r.window_end = s.at("window").at(1).get<double>();
  r.window_clipped = s.at("window_clipped").get<bool>();
  if (s.contains("summary_periods")) {
    r.summary_periods = s.at("summary_periods").get<int>();
    r.period = nan_if_null(s.at("period"));
  } else {
    r.summary_time = s.at("summary_time").get<double>();
  }
  const auto& st = s.at("stats");
  r.stats = {st.at("steps").get<long>(),     st.at("accepted").get<long>(),
             st.at("rejected").get<long>(),  st.at("f_evals").get<long>(),
             st.at("jacobians").get<long>(), st.at("lu_decompositions").get<long>(),
             st.at("wall_seconds").get<double>()};
  r.q_end = map_of(s.at("q_end"));
  r.qd_end = map_of(s.at("qd_end"));
  r.columns = std::move(columns);
  for (const auto& [name, e] : s.at("extremes").items()) {
    ColumnExtremes x;
    x.min = nan_if_null(e.at("min"));
    x.max = nan_if_null(e.at("max"));
    x.t_min = x.t_max = std::numeric_limits<double>::quiet_NaN();  // summary.json has no times
    r.extremes[name] = x;
  }
  r.constraint_residual_max = s.at("constraint_residual_max").get<double>();
  r.constraints = s.at("constraints").get<std::vector<std::string>>();
  r.parameters = map_of(s.at("parameters"));
  r.output_dt = s.at("output_dt").get<double>();
  r.initial_correction_position = s.at("initial_correction").at("position").get<double>();
  r.initial_correction_velocity = s.at("initial_correction").at("velocity").get<double>();
  if (s.contains("initial_state")) {
    const auto& i = s.at("initial_state");
    r.initial_state = InitialState{map_of(i.at("q")), i.at("force_imbalance").get<double>(),
                                   map_of(i.at("holding_forces"))};
  }
  const auto& a = s.at("accuracy");
  r.accuracy = {a.at("reliable").get<bool>(), a.at("rtol").get<double>(),
                a.at("atol").get<double>(), a.value("reason", std::string())};
  r.complete = s.at("complete").get<bool>();
  if (s.contains("switching")) r.switching = s.at("switching");
  if (s.contains("rank")) r.rank = s.at("rank");
  if (s.contains("stopped"))
    r.stopped = RunEnd{s.at("stopped").at("t").get<double>(), "",
                       s.at("stopped").at("reason").get<std::string>()};
  else if (s.contains("failure"))
    r.failure = RunEnd{s.at("failure").at("t").get<double>(),
                       s.at("failure").at("status").get<std::string>(),
                       s.at("failure").at("reason").get<std::string>()};
  if (s.contains("t_reached")) r.t_reached = s.at("t_reached").get<double>();
  for (const auto& [k, v] : s.items()) {
    bool generic = false;
    for (const char* g : kGenericKeys) generic = generic || k == g;
    if (!generic) r.additions[k] = v;
  }
  return r;
}

}  // namespace pcsim::sim
