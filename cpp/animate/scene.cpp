// Reading a run directory into the frames of its animation (scene.hpp).
#include "animate/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/format.hpp"
#include "sim/time_series_file.hpp"

namespace pcsim::animate {

namespace fs = std::filesystem;

namespace {

constexpr std::uintmax_t kMaxTableBytes = 2ull << 30;  // 2 GB: a run's longest time series
constexpr std::uintmax_t kMaxJsonBytes = 64ull << 20;

nlohmann::json read_json(const fs::path& f, const std::string& half_written) {
  const std::string text = sim::read_run_file(f, kMaxJsonBytes, "a pcsim summary");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw InputError(f.string() + ": not a complete JSON file; " + half_written);
  }
}

std::vector<Event> read_events(const fs::path& f) {
  std::vector<Event> out;
  std::error_code ec;
  if (!fs::exists(f, ec)) return out;
  const std::string text = sim::read_run_file(f, kMaxTableBytes, "a pcsim events table");
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto fields = sim::split_csv_fields(line);
    if (fields.size() < 5) continue;
    Event e;
    e.t = std::strtod(fields[0].c_str(), nullptr);
    e.kind = fields[1];
    e.constraint = fields[2];
    e.mode_after = fields[4];
    if (std::isfinite(e.t)) out.push_back(e);
  }
  return out;
}

}  // namespace

Scene read_scene(const fs::path& dir, int max_frames) {
  const std::string d = dir.string();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(d + ": not a directory; expected the output directory of `pcsim run` or `pcsim steady`");
  const std::string rerun = "the run looks half-written or failed: rerun the command that wrote it";
  const fs::path run_sum = dir / "summary.json", steady_sum = dir / "steady.json";
  Scene s;
  s.steady = !fs::exists(run_sum, ec) && fs::exists(steady_sum, ec);
  if (!fs::exists(run_sum, ec) && !s.steady)
    throw InputError(d + ": not a pcsim run directory (expected summary.json from `pcsim run` or "
                         "steady.json from `pcsim steady`, with timeseries.csv or timeseries.npy and model.toml)");
  nlohmann::json sum = read_json(s.steady ? steady_sum : run_sum, rerun);
  if (!sum.is_object() || !sum.contains("complete") || sum["complete"] != true)
    throw InputError((s.steady ? steady_sum : run_sum).string() +
                     ": the run is not complete (\"complete\" is not true); " + rerun);
  if (s.steady) {
    if (!sum.contains("summary") || !sum["summary"].is_object())
      throw InputError(steady_sum.string() + ": no period summary (written with --no-summary?): "
                       "nothing to animate; rerun pcsim steady with its period summary");
    sum = sum["summary"];
  }
  s.title = sum.value("case", std::string("run"));
  s.model = sum.value("model", std::string("model"));
  const fs::path model_file = dir / "model.toml";
  if (!fs::exists(model_file, ec))
    throw InputError(d + ": no model.toml (the model of the run, which pcsim run and pcsim steady "
                         "write since pcsim animate exists): rerun the case to animate it");
  {
    std::ifstream in(model_file);
    std::string first;
    std::getline(in, first);
    const std::string prefix = "# pcsim run: the ";
    s.model_file = first.rfind(prefix, 0) == 0 ? first.substr(prefix.size()) : model_file.string();
  }

  // The time series, timeseries.csv or timeseries.npy (output.format = "npy"): the same rows.
  const sim::TimeSeries table = sim::read_time_series(sim::time_series_file(dir), kMaxTableBytes, rerun);
  const std::string series_file = table.file.string();
  std::map<std::string, int> col;
  for (std::size_t i = 0; i < table.header.size(); ++i) col[table.header[i]] = static_cast<int>(i);

  const modelfile::DrawEvaluator ev(model_file);
  if (ev.spec().empty())
    throw InputError(d + ": the model '" + s.model + "' has nothing to draw: add a [model.draw] "
                     "table (points, lines, polygons, circles, force arrows; README, \"pcsim "
                     "animate\") to the " + s.model_file + ", then rerun the case");
  s.spec = ev.spec();
  s.spatial = s.spec.spatial;
  s.magnify = s.spec.magnify;

  // The inputs of the drawing: t, the coordinates and velocities from the row, the parameters
  // from the summary (their defaults where it has none).
  const auto& names = ev.input_names();
  const std::size_t n_q = 1 + 2 * ev.coordinates().size();
  std::vector<int> input_col;
  for (std::size_t i = 0; i < n_q; ++i) {
    const auto it = col.find(names[i]);
    if (it == col.end())
      throw InputError(series_file + ": no column '" + names[i] + "', which the model '" + s.model +
                       "' of model.toml has; the directory mixes two runs: rerun the case");
    input_col.push_back(it->second);
  }
  std::vector<double> inputs(names.size(), 0.0);
  const nlohmann::json params = sum.contains("parameters") && sum["parameters"].is_object()
                                    ? sum["parameters"] : nlohmann::json::object();
  for (std::size_t i = n_q; i < names.size(); ++i) {
    inputs[i] = ev.parameter_defaults()[i - n_q].second;
    if (params.contains(names[i]) && params[names[i]].is_number()) inputs[i] = params[names[i]].get<double>();
  }
  std::vector<int> force_col;
  for (const auto& sh : s.spec.shapes) {
    if (sh.kind != modelfile::DrawShape::Kind::arrow) continue;
    const auto it = col.find(sh.force);
    if (it == col.end())
      throw InputError(series_file + ": no column '" + sh.force + "' (" + sh.key + ".force)");
    force_col.push_back(it->second);
  }
  const std::size_t first_label = table.header.size() - static_cast<std::size_t>(table.label_columns);
  for (std::size_t c = first_label; c < table.header.size(); ++c) s.contacts.push_back(table.header[c].substr(5));

  // Every row drawn (the moving mean needs them all).
  const std::size_t N = table.rows(), K = ev.size(), P = s.spec.points.size();
  s.rows = N;
  std::vector<double> all(N * K);
  std::vector<double> times(N);
  for (std::size_t r = 0; r < N; ++r) {
    for (std::size_t i = 0; i < n_q; ++i) inputs[i] = table.at(r, static_cast<std::size_t>(input_col[i]));
    times[r] = inputs[0];
    ev.evaluate(inputs, &all[r * K]);
  }
  const double period = ev.period(inputs);
  const double span = times.back() - times.front();
  s.mean_window = std::isfinite(period) && period > 0 && period < span ? period : 0.0;

  // The frames: every k-th row, the last row, and the row of each event (ticks stay exact on the
  // timeline; the frame nearest an event shows it).
  s.events = read_events(dir / "events.csv");
  const std::size_t frames = static_cast<std::size_t>(std::max(2, max_frames));
  const std::size_t stride = (N + frames - 1) / frames;
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < N; r += std::max<std::size_t>(1, stride)) rows.push_back(r);
  rows.push_back(N - 1);
  if (s.events.size() <= frames)
    for (const Event& e : s.events) {
      const auto it = std::lower_bound(times.begin(), times.end(), e.t);
      std::size_t r = static_cast<std::size_t>(it - times.begin());
      if (r >= N) r = N - 1;
      if (r > 0 && std::abs(times[r - 1] - e.t) <= std::abs(times[r] - e.t)) --r;
      rows.push_back(r);
    }
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());

  // The moving mean of the points (over one excitation period centred on the frame, or the
  // whole run), by prefix sums over the rows.
  const std::size_t M = 3 * P;
  std::vector<double> prefix((N + 1) * M, 0.0);
  for (std::size_t r = 0; r < N; ++r)
    for (std::size_t k = 0; k < M; ++k) prefix[(r + 1) * M + k] = prefix[r * M + k] + all[r * K + k];
  for (std::size_t r : rows) {
    std::size_t a = 0, b = N;
    if (s.mean_window > 0) {
      a = static_cast<std::size_t>(std::lower_bound(times.begin(), times.end(), times[r] - s.mean_window / 2) - times.begin());
      b = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), times[r] + s.mean_window / 2) - times.begin());
    }
    std::vector<double> m(M);
    for (std::size_t k = 0; k < M; ++k) m[k] = (prefix[b * M + k] - prefix[a * M + k]) / double(b - a);
    std::vector<double> v(all.begin() + static_cast<std::ptrdiff_t>(r * K), all.begin() + static_cast<std::ptrdiff_t>((r + 1) * K));
    // A point that follows another moves with the other's magnified displacement, at its true
    // offset from it: its mean is the leader's plus the offset, its deviation the leader's.
    for (std::size_t i = 0; i < P; ++i) {
      const int j = s.spec.points[i].follows;
      if (j < 0) continue;
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t a_i = 3 * i + k, a_j = 3 * static_cast<std::size_t>(j) + k;
        m[a_i] = m[a_j] + (v[a_i] - v[a_j]);
        v[a_i] = m[a_i] + (v[a_j] - m[a_j]);
      }
    }
    s.t.push_back(times[r]);
    s.row.push_back(r);
    s.values.push_back(std::move(v));
    s.mean.push_back(std::move(m));
    std::vector<double> f;
    for (int c : force_col) f.push_back(table.at(r, static_cast<std::size_t>(c)));
    s.forces.push_back(std::move(f));
    std::vector<std::string> modes;
    for (std::size_t c = first_label; c < table.header.size(); ++c) modes.push_back(table.label(r, c));
    s.modes.push_back(std::move(modes));
  }
  return s;
}

Scene read_modes_scene(const fs::path& dir, int max_frames) {
  const std::string d = dir.string();
  const std::string rerun = "the directory looks half-written: rerun pcsim modes";
  const fs::path mj = dir / "modes.json";
  std::error_code ec;
  if (!fs::exists(mj, ec))
    throw InputError(d + ": no modes.json (a `pcsim modes --vary` directory has only the traced "
                         "eigenvalues: nothing to animate; run pcsim modes without --vary)");
  const nlohmann::json j = read_json(mj, rerun);
  auto bad = [&](const std::string& what) { return InputError(mj.string() + ": " + what + "; " + rerun); };
  if (!j.is_object() || !j.contains("modes") || !j["modes"].is_array() || !j.contains("reference") ||
      !j["reference"].is_object() || !j["reference"].contains("q") || !j["reference"]["q"].is_object() ||
      !j.contains("coordinates") || !j["coordinates"].is_array())
    throw bad("expected pcsim modes' modes.json (modes, reference.q, coordinates)");
  Scene s;
  s.steady = true;  // each mode's cycle is looped
  s.title = j.value("case", std::string("modes"));
  s.model = j.value("model", std::string("model"));
  const fs::path model_file = dir / "model.toml";
  if (!fs::exists(model_file, ec))
    throw InputError(d + ": no model.toml (the model of the modes, which pcsim modes writes since pcsim "
                         "animate draws modes): rerun pcsim modes to animate them");
  {
    std::ifstream in(model_file);
    std::string first;
    std::getline(in, first);
    const std::string prefix = "# pcsim modes: the ";
    s.model_file = first.rfind(prefix, 0) == 0 ? first.substr(prefix.size()) : model_file.string();
  }
  const modelfile::DrawEvaluator ev(model_file);
  if (ev.spec().empty())
    throw InputError(d + ": the model '" + s.model + "' has nothing to draw: add a [model.draw] "
                     "table (points, lines, polygons, circles, force arrows; README, \"pcsim "
                     "animate\") to the " + s.model_file + ", then rerun pcsim modes");
  s.spec = ev.spec();
  s.spatial = s.spec.spatial;
  s.magnify = 1;
  if (j["modes"].empty()) throw bad("no modes (a tangent space of dimension 0): nothing to animate");

  // The inputs: t (the excitation's phase when held at one, else 0), q and q_d of the reference,
  // the parameters linearized at (their defaults where modes.json has none).
  const auto& names = ev.input_names();
  const auto& coords = ev.coordinates();
  const std::size_t nc = coords.size(), n_q = 1 + 2 * nc;
  const auto& ref = j["reference"];
  double t_ref = 0;
  if (j.contains("excitation") && j["excitation"].is_object() && j["excitation"].value("mode", "") == "phase" &&
      j["excitation"]["phase"].is_number() && j["excitation"]["period"].is_number())
    t_ref = j["excitation"]["phase"].get<double>() / (2 * 3.14159265358979323846) * j["excitation"]["period"].get<double>();
  std::vector<double> inputs(names.size(), 0.0);
  std::vector<int> q_input(nc, -1);  // the input index of each coordinate
  for (std::size_t i = 0; i < n_q; ++i) {
    const std::string& nm = names[i];
    if (nm == "t") {
      inputs[i] = t_ref;
      continue;
    }
    const bool vel = nm.size() > 2 && nm.compare(nm.size() - 2, 2, "_d") == 0;
    const nlohmann::json& table = vel ? ref.value("qd", nlohmann::json::object()) : ref["q"];
    if (!table.is_object() || !table.contains(nm) || !table[nm].is_number())
      throw InputError(mj.string() + ": no reference value of '" + nm + "', which the model '" + s.model +
                       "' of model.toml has; the directory mixes two models: rerun pcsim modes");
    inputs[i] = table[nm].get<double>();
    if (!vel)
      for (std::size_t c = 0; c < nc; ++c)
        if (coords[c] == nm) q_input[c] = static_cast<int>(i);
  }
  const nlohmann::json params = j.contains("parameters") && j["parameters"].is_object() ? j["parameters"]
                                                                                       : nlohmann::json::object();
  for (std::size_t i = n_q; i < names.size(); ++i) {
    inputs[i] = ev.parameter_defaults()[i - n_q].second;
    if (params.contains(names[i]) && params[names[i]].is_number()) inputs[i] = params[names[i]].get<double>();
  }
  const std::size_t K = ev.size(), P = s.spec.points.size();
  std::size_t arrows = 0;
  for (const auto& sh : s.spec.shapes) arrows += sh.kind == modelfile::DrawShape::Kind::arrow;
  std::vector<double> base(K);
  ev.evaluate(inputs, base.data());
  std::vector<double> ref_points(base.begin(), base.begin() + static_cast<std::ptrdiff_t>(3 * P));
  // The drawing's size at the reference: the span of its points (and circles' diameters).
  double extent = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t p = 0; p < P; ++p)
      if (std::isfinite(ref_points[3 * p + k])) {
        lo = std::min(lo, ref_points[3 * p + k]);
        hi = std::max(hi, ref_points[3 * p + k]);
      }
    if (hi > lo) extent = std::max(extent, hi - lo);
  }
  {
    std::size_t vi = 3 * P;
    for (const auto& sh : s.spec.shapes) {
      if (sh.kind == modelfile::DrawShape::Kind::circle && std::isfinite(base[vi])) extent = std::max(extent, 2 * std::abs(base[vi]));
      vi += sh.kind == modelfile::DrawShape::Kind::circle ? 1 : sh.kind == modelfile::DrawShape::Kind::arrow ? 3 : 0;
    }
  }
  if (!(extent > 0)) extent = 1;

  const std::size_t n_modes = j["modes"].size();
  const std::size_t per = static_cast<std::size_t>(std::clamp<long>(max_frames / static_cast<long>(n_modes), 8, 48));
  const double two_pi = 2 * 3.14159265358979323846;
  auto at = [&](const std::vector<double>& vr, const std::vector<double>& vi, double a, double phi, std::vector<double>& out) {
    std::vector<double> in = inputs;
    for (std::size_t c = 0; c < nc; ++c)
      if (q_input[c] >= 0) in[static_cast<std::size_t>(q_input[c])] += a * (vr[c] * std::cos(phi) - vi[c] * std::sin(phi));
    out.assign(K, 0.0);
    ev.evaluate(in, out.data());
  };
  auto largest_move = [&](const std::vector<double>& v) {
    double m = 0;
    for (std::size_t k = 0; k < 3 * P; ++k)
      if (std::isfinite(v[k])) m = std::max(m, std::abs(v[k] - ref_points[k]));
    return m;
  };
  double qscale = 1;
  for (std::size_t c = 0; c < nc; ++c)
    if (q_input[c] >= 0) qscale = std::max(qscale, std::abs(inputs[static_cast<std::size_t>(q_input[c])]));
  std::vector<double> vals;
  for (std::size_t m = 0; m < n_modes; ++m) {
    const nlohmann::json& md = j["modes"][m];
    if (!md.is_object() || !md.contains("shape") || !md["shape"].is_object()) throw bad("a mode without a shape");
    std::vector<double> vr(nc, 0.0), vim(nc, 0.0);
    for (std::size_t c = 0; c < nc; ++c) {
      const auto& sh = md["shape"];
      if (!sh.contains(coords[c]) || !sh[coords[c]].is_object() || !sh[coords[c]]["re"].is_number() ||
          !sh[coords[c]]["im"].is_number())
        throw InputError(mj.string() + ": mode " + std::to_string(m + 1) + " has no shape component '" + coords[c] +
                         "', which the model of model.toml has; the directory mixes two models: rerun pcsim modes");
      vr[c] = sh[coords[c]]["re"].get<double>();
      vim[c] = sh[coords[c]]["im"].get<double>();
    }
    // The amplitude: the largest drawn displacement (probed with a small amplitude, where the
    // drawing is linear in it) scaled to 15% of the drawing's size.
    const double h = 1e-6 * qscale;
    double d1 = 0;
    for (std::size_t f = 0; f < per; ++f) {
      at(vr, vim, h, two_pi * double(f) / double(per), vals);
      d1 = std::max(d1, largest_move(vals) / h);
    }
    ModePage pg;
    const std::string kind = md.value("kind", std::string("mode"));
    const int number = md.value("mode", static_cast<int>(m + 1));
    pg.label = "mode " + std::to_string(number) + " (" + kind + ")";
    const double re = md.value("re", 0.0), im = md.value("im", 0.0);
    std::string text = "eigenvalue " + format_significant(re, 6) +
                       (md.value("pair", false) ? " +- " + format_significant(im, 6) + "i" : "") + " 1/s";
    auto numtext = [&](const char* key) {
      return md.contains(key) && md[key].is_number() ? format_significant(md[key].get<double>(), 6) : std::string("-");
    };
    text += "; natural frequency " + numtext("natural_frequency_rad_s") + " rad/s (" + numtext("natural_frequency_hz") +
            " Hz); damped frequency " + numtext("damped_frequency_rad_s") + " rad/s; damping ratio " + numtext("damping_ratio");
    if (md.contains("dominant") && md["dominant"].is_array() && !md["dominant"].empty()) {
      text += "; dominant:";
      for (const auto& dname : md["dominant"])
        if (dname.is_string()) text += " " + dname.get<std::string>();
    }
    text += md.value("pair", false) ? ". Shown: q = q_ref + a Re(v e^{i phi}), phi = omega tau over one cycle."
                                    : ". A real eigenvalue (no oscillation): shown as the standing oscillation "
                                      "q = q_ref + a v cos(phi) of its shape.";
    pg.text = text;
    if (d1 > 0 && std::isfinite(d1)) {
      pg.amplitude = 0.15 * extent / d1;
      pg.amplitude_text = "mode shape amplitude a = " + format_significant(pg.amplitude, 4) +
                          " (largest component of the shape = 1): its largest drawn displacement is 15% of the "
                          "drawing's size (" + format_significant(0.15 * extent, 4) + "); not to scale with any real motion";
    } else {
      pg.amplitude = 0;
      pg.amplitude_text = "this mode moves no drawn point (its shape is in coordinates the drawing does not use)";
    }
    pg.first = s.t.size();
    pg.count = per;
    for (std::size_t f = 0; f < per; ++f) {
      const double phi = two_pi * double(f) / double(per);
      at(vr, vim, pg.amplitude, phi, vals);
      s.t.push_back(phi);
      s.row.push_back(0);
      s.values.push_back(vals);
      s.mean.push_back(ref_points);
      s.forces.push_back(std::vector<double>(arrows, std::nan("")));
      s.modes.push_back({});
    }
    s.mode_pages.push_back(pg);
  }
  s.rows = n_modes;
  return s;
}

}  // namespace pcsim::animate
