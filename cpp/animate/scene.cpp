// Reading a run directory into the frames of its animation (scene.hpp).
#include "animate/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/format.hpp"

namespace pcsim::animate {

namespace fs = std::filesystem;

namespace {

constexpr std::uintmax_t kMaxTableBytes = 2ull << 30;  // 2 GB: a run's longest time series
constexpr std::uintmax_t kMaxJsonBytes = 64ull << 20;

std::string read_file(const fs::path& f, std::uintmax_t limit, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(f, ec))
    throw InputError(f.string() + ": expected " + what + " (a regular file)");
  const auto size = fs::file_size(f, ec);
  if (ec || size > limit)
    throw InputError(f.string() + ": expected " + what + " of at most " + format_number(double(limit)) + " bytes");
  std::ifstream in(f, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in && !in.eof()) throw InputError(f.string() + ": cannot read " + what);
  return s.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::size_t b = 0;
  while (true) {
    const std::size_t e = line.find(',', b);
    out.push_back(line.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return out;
}

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> numbers;      // per row, per column (NaN for text columns)
  std::vector<std::vector<std::string>> texts;   // per row, the mode_ columns
  std::vector<int> text_columns;
};

Table read_table(const fs::path& f, const std::string& half_written) {
  const std::string text = read_file(f, kMaxTableBytes, "a pcsim time series");
  if (text.empty() || text.back() != '\n')
    throw InputError(f.string() + ": the time series ends in a torn row; " + half_written);
  Table t;
  std::size_t pos = text.find('\n');
  t.header = split(text.substr(0, pos));
  if (t.header.empty() || t.header[0] != "t")
    throw InputError(f.string() + ": expected a pcsim time series (a header starting with 't')");
  for (std::size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i].rfind("mode_", 0) == 0) t.text_columns.push_back(static_cast<int>(i));
  ++pos;
  std::size_t line_no = 1;
  while (pos < text.size()) {
    const std::size_t e = text.find('\n', pos);
    const std::string line = text.substr(pos, e - pos);
    pos = e + 1;
    ++line_no;
    const auto fields = split(line);
    if (fields.size() != t.header.size())
      throw InputError(f.string() + ":" + std::to_string(line_no) + ": expected " +
                       std::to_string(t.header.size()) + " fields, got " + std::to_string(fields.size()) +
                       "; " + half_written);
    std::vector<double> row(fields.size(), std::nan(""));
    std::vector<std::string> modes;
    std::size_t k = 0;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (k < t.text_columns.size() && t.text_columns[k] == static_cast<int>(i)) {
        modes.push_back(fields[i]);
        ++k;
        continue;
      }
      if (fields[i].empty()) continue;  // a value the run has not (fstar in flight): NaN
      char* end = nullptr;
      row[i] = std::strtod(fields[i].c_str(), &end);
      if (*end != '\0')
        throw InputError(f.string() + ":" + std::to_string(line_no) + ": column '" + t.header[i] +
                         "': expected a number, got '" + fields[i].substr(0, 40) + "'");
    }
    t.numbers.push_back(std::move(row));
    t.texts.push_back(std::move(modes));
  }
  if (t.numbers.empty()) throw InputError(f.string() + ": the time series has no rows; " + half_written);
  return t;
}

nlohmann::json read_json(const fs::path& f, const std::string& half_written) {
  const std::string text = read_file(f, kMaxJsonBytes, "a pcsim summary");
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
  const std::string text = read_file(f, kMaxTableBytes, "a pcsim events table");
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto fields = split(line);
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
                         "steady.json from `pcsim steady`, with timeseries.csv and model.toml)");
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

  const fs::path csv = dir / "timeseries.csv";
  const Table table = read_table(csv, rerun);
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
      throw InputError(csv.string() + ": no column '" + names[i] + "', which the model '" + s.model +
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
      throw InputError(csv.string() + ": no column '" + sh.force + "' (" + sh.key + ".force)");
    force_col.push_back(it->second);
  }
  for (int c : table.text_columns) s.contacts.push_back(table.header[static_cast<std::size_t>(c)].substr(5));

  // Every row drawn (the moving mean needs them all).
  const std::size_t N = table.numbers.size(), K = ev.size(), P = s.spec.points.size();
  s.rows = N;
  std::vector<double> all(N * K);
  std::vector<double> times(N);
  for (std::size_t r = 0; r < N; ++r) {
    for (std::size_t i = 0; i < n_q; ++i) inputs[i] = table.numbers[r][static_cast<std::size_t>(input_col[i])];
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
    for (int c : force_col) f.push_back(table.numbers[r][static_cast<std::size_t>(c)]);
    s.forces.push_back(std::move(f));
    s.modes.push_back(table.texts[r]);
  }
  return s;
}

}  // namespace pcsim::animate
