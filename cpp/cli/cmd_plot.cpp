// `pcsim plot DIR`: PNG figures of a `pcsim run` output directory with gnuplot. A model with a
// client draws the client's figures (sim::Client::figures). Any other model: its
// coordinates, its non-zero reactions and its outputs (at most six curves per figure). Each
// figure shows the whole run, and below it the summary window when that is part of the run.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <set>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include "cli/commands.hpp"
#include "cli/plot_response.hpp"
#include "common/error.hpp"
#include "common/gnuplot.hpp"
#include "modes/cli/plot_modes.hpp"
#include "sim/client.hpp"
#include "sim/time_series_file.hpp"

namespace {

namespace fs = std::filesystem;

std::string quoted(const std::string& s) { return pcsim::gnuplot_quoted(s); }

std::string num_exact(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string num_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

using Figure = pcsim::sim::PlotFigure;

// Switching runs (issue 12): the intervals in which a contact flies or slides, from events.csv
// (each event's mode_after holds until the contact's next event) and the initial modes of
// summary.json, shaded on the figures.
struct Band {
  double a = 0, b = 0;
  bool slip = false;
};

std::vector<Band> mode_bands(const fs::path& events, const nlohmann::json& s, double t_end) {
  std::vector<Band> out;
  if (!fs::exists(events) || !s.contains("switching")) return out;
  pcsim::cli::check_plot_table(events, pcsim::cli::kMaxPlotTableBytes, false);
  std::map<std::string, std::pair<std::string, double>> current;  // constraint -> mode, since
  for (const auto& [name, c] : s["switching"]["contacts"].items())
    current[name] = {c.value("initial_mode", std::string("contact")), 0.0};
  auto close = [&](const std::pair<std::string, double>& m, double t) {
    if ((m.first == "flight" || m.first == "slip") && t > m.second)
      out.push_back({m.second, t, m.first == "slip"});
  };
  std::ifstream in(events);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::string t, kind, constraint, before, after;
    std::getline(ls, t, ',');
    std::getline(ls, kind, ',');
    std::getline(ls, constraint, ',');
    std::getline(ls, before, ',');
    std::getline(ls, after, ',');
    const double tt = std::strtod(t.c_str(), nullptr);
    auto it = current.find(constraint);
    if (it == current.end()) continue;
    close(it->second, tt);
    it->second = {after, tt};
  }
  for (const auto& [name, m] : current) close(m, t_end);
  return out;
}

// The time series as gnuplot reads it: timeseries.csv itself, or the rows of timeseries.npy
// (output.format = "npy") as the same CSV text, written beside the figures as plots.csv.
struct PlotSeries {
  std::vector<std::string> header;
  std::string data_name;
  std::optional<pcsim::cli::PlotData> data;
};

PlotSeries plot_series(const fs::path& file) {
  PlotSeries p;
  if (file.extension() != ".npy") {
    p.header = pcsim::cli::check_plot_table(file, pcsim::cli::kMaxPlotTableBytes, true).header;
    p.data_name = file.filename().string();
    return p;
  }
  const pcsim::sim::TimeSeries rows = pcsim::sim::read_time_series(
      file, pcsim::cli::kMaxPlotTableBytes,
      "the directory looks half-written (a run that was stopped, or a copy in progress): rerun "
      "the command that wrote it");
  p.header = rows.header;
  p.data_name = "plots.csv";
  p.data = pcsim::cli::PlotData{p.data_name, pcsim::sim::time_series_csv(rows)};
  return p;
}

void plot_run(const std::string& dir_text);

void plot(const std::string& dir_text) {
  const fs::path dir(dir_text);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw pcsim::InputError(dir_text + ": not a directory; expected the output directory of `pcsim "
                                       "run`, `pcsim steady` or `pcsim response`");
  if (pcsim::cli::is_response_dir(dir)) {  // `pcsim response`: the response curves
    pcsim::cli::plot_response(dir);
    return;
  }
  if (pcsim::cli::is_modes_dir(dir)) {  // `pcsim modes --vary`: the eigenvalue trace
    pcsim::cli::plot_modes(dir);
    return;
  }
  try {
    plot_run(dir_text);
  } catch (const nlohmann::json::exception& e) {
    throw pcsim::InputError(dir_text + ": not a complete pcsim summary (" + e.what() +
                            "); the directory looks half-written: rerun the command that wrote it");
  }
}

void plot_run(const std::string& dir_text) {
  const fs::path dir(dir_text);
  // `pcsim run` writes summary.json; `pcsim steady` writes steady.json, whose "summary" is the
  // same summary of one period of the orbit.
  const fs::path series = pcsim::sim::time_series_file(dir), run_sum = dir / "summary.json",
                 steady_sum = dir / "steady.json";
  const bool steady = !fs::exists(run_sum) && fs::exists(steady_sum);
  const fs::path sum = steady ? steady_sum : run_sum;
  if (!fs::exists(series) || !fs::exists(sum))
    throw pcsim::InputError(dir_text + ": expected the output of `pcsim run` (timeseries.csv or "
                                       "timeseries.npy, and summary.json), `pcsim steady` (the "
                                       "same with steady.json) or `pcsim response` (response.csv "
                                       "and response.json)");
  nlohmann::json s = pcsim::cli::read_plot_json(sum, pcsim::cli::kMaxPlotJsonBytes);
  if (steady) {
    if (!s.is_object() || !s.contains("summary"))
      throw pcsim::InputError(sum.string() + ": not a complete steady.json (no 'summary'); rerun pcsim steady");
    s = s["summary"];
  }
  if (!s.is_object()) throw pcsim::InputError(sum.string() + ": not a pcsim summary (not a JSON object)");
  // The time series checked whole (regular file, bounded size, no torn or short row) before
  // gnuplot sees it: a half-written directory is refused, not half-drawn.
  const PlotSeries table = plot_series(series);
  std::map<std::string, int> col;
  for (std::size_t i = 0; i < table.header.size(); ++i) col[table.header[i]] = static_cast<int>(i) + 1;
  if (!col.count("t")) throw pcsim::InputError(series.string() + ": header has no column 't'");

  const double w0 = s.at("window").at(0).get<double>(), w1 = s.at("window").at(1).get<double>();
  const std::string name = s.value("case", std::string("case"));
  std::vector<Figure> figs;
  // A model's client draws its own figures (the sieve: theta, R_u, f*, x and y); any other
  // model gets the generic ones.
  if (const auto client = pcsim::sim::find_client(s.value("model", std::string()))) {
    std::set<std::string> columns;
    for (const auto& [cname, idx] : col) columns.insert(cname);
    figs = client->figures(s, columns, series.string());
  }
  if (figs.empty()) {
    // Any model: the coordinates, the reactions that are not identically zero, and the
    // outputs, at most kPerFigure curves per figure (numbered figures beyond that).
    constexpr std::size_t kPerFigure = 6;
    std::vector<std::string> coords, reactions, outputs;
    const auto& ex = s.at("extremes");
    std::vector<std::pair<int, std::string>> ordered;
    for (const auto& [cname, idx] : col) ordered.push_back({idx, cname});
    std::sort(ordered.begin(), ordered.end());
    std::set<std::string> coordinate_names;
    for (const auto& [idx, cname] : ordered)
      if (cname.rfind("R_", 0) == 0) coordinate_names.insert(cname.substr(2));
    for (const auto& [idx, cname] : ordered) {
      if (cname == "t" || cname == "residual_pos" || cname == "residual_vel") continue;
      if (cname.rfind("mode_", 0) == 0) continue;  // the contacts' modes: shaded, not plotted
      if (coordinate_names.count(cname)) coords.push_back(cname);
      else if (cname.rfind("R_", 0) == 0) {
        const bool zero = ex.contains(cname) && ex[cname]["min"].is_number() &&
                          ex[cname]["min"].get<double>() == 0.0 && ex[cname]["max"].get<double>() == 0.0;
        if (!zero) reactions.push_back(cname);
      } else if (cname.size() > 2 && cname.compare(cname.size() - 2, 2, "_d") == 0 &&
                 coordinate_names.count(cname.substr(0, cname.size() - 2))) {
        continue;  // velocities: in the time series, not plotted by default
      } else {
        outputs.push_back(cname);
      }
    }
    auto add = [&](const std::vector<std::string>& names, const std::string& stem,
                   const std::string& title, const std::string& ylabel) {
      for (std::size_t start = 0; start < names.size(); start += kPerFigure) {
        Figure fig;
        const std::size_t part = start / kPerFigure + 1;
        fig.file = stem + (names.size() > kPerFigure ? "_" + std::to_string(part) : "") + ".png";
        fig.title = title;
        fig.ylabel = ylabel;
        for (std::size_t k = start; k < std::min(names.size(), start + kPerFigure); ++k)
          fig.curves.push_back({names[k], names[k]});
        figs.push_back(fig);
      }
    };
    add(coords, "coordinates", "Coordinates q(t)", "q");
    add(reactions, "reactions", "Reaction forces R(t) (generalized, by coordinate)", "R");
    add(outputs, "outputs", "Outputs", "value");
  }

  const std::vector<Band> bands = mode_bands(dir / "events.csv", s, w1);
  // The whole-run panel shades at most this many bands (a long hopping run has one per period;
  // the window panel shows them all).
  constexpr std::size_t kMaxBandsWholeRun = 400;
  auto shade = [&](std::ostringstream& out, double lo, double hi) {
    int id = 100;
    std::size_t n = 0;
    for (const Band& b : bands)
      if (b.b > lo && b.a < hi) ++n;
    if (hi - lo > (w1 - w0) * 1.5 && n > kMaxBandsWholeRun) return;
    for (const Band& b : bands) {
      if (!(b.b > lo && b.a < hi)) continue;
      out << "set object " << id++ << " rect from " << std::max(b.a, lo) << ", graph 0 to "
          << std::min(b.b, hi) << ", graph 1 fc rgb '" << (b.slip ? "#f4a6a6" : "#a6c8f4")
          << "' fs solid 0.5 noborder behind\n";
    }
  };
  auto unshade = [&](std::ostringstream& out) {
    for (std::size_t k = 0; k < bands.size() && k < 100000; ++k) out << "unset object " << 100 + k << "\n";
  };

  std::ostringstream g;
  g << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
       "  set terminal pngcairo size 1000,750 font 'sans,10' noenhanced\n"
       "} else {\n"
       "  set terminal png size 1000,750 noenhanced\n"
       "}\n"
       "set datafile separator ','\n"
       "set grid\nset key top right opaque box\nset format y '%.3g'\n"
       "set offsets 0, 0, graph 0.3, graph 0.05\n";
  for (const auto& fig : figs) {
    g << "set output " << quoted(fig.file) << "\n";
    // Two panels (whole run above, summary window below) when the window is part of the run.
    const int panels = w0 > 0 ? 2 : 1;
    g << "set multiplot layout " << panels << ",1 title " << quoted(name + ": " + fig.title) << "\n";
    for (int panel = 0; panel < panels; ++panel) {
      g << "unset object 1\nunset arrow 1\n";
      if (panel == 0) {
        if (panels == 2) {
          g << "set title 'whole run (shaded: summary window)'\n";
          g << "set object 1 rect from " << w0 << ", graph 0 to " << w1
            << ", graph 1 fc rgb '#ffd080' fs solid 0.6 noborder behind\n";
          g << "set arrow 1 from " << w0 << ", graph 0 to " << w0
            << ", graph 1 nohead lc rgb '#e08000' lw 1.5 dt 3\n";
        } else {
          g << "set title 'whole run (the summary window)'\n";
        }
        g << "set xrange [*:*]\n";
      } else {
        char title[128];
        std::snprintf(title, sizeof title, "summary window t = %.4f .. %.4f s", w0, w1);
        g << "set title " << quoted(title) << "\n";
        g << "set xrange [" << w0 << ":" << w1 << "]\n";
      }
      if (!bands.empty()) {
        unshade(g);
        double lo = -1e300, hi = 1e300;
        if (panel == 1) {
          lo = w0;
          hi = w1;
        }
        shade(g, lo, hi);
      }
      g << "set xlabel 't [s]'\nset ylabel " << quoted(fig.ylabel) << "\n";
      g << "unset label 1\n";
      if (panel == 1 && fig.has_hline && !fig.hline_in_window)
        g << "set label 1 " << quoted(fig.hline_label + " = " + num_text(fig.hline) +
                                      ": off this scale, see the upper panel")
          << " at graph 0.02, graph 0.93\n";
      g << "plot ";
      bool first = true;
      for (const auto& [c, legend] : fig.curves) {
        g << (first ? "" : ", ") << quoted(table.data_name) << " every ::1 using " << col["t"] << ":";
        if (fig.offset != 0.0 || fig.scale != 1.0)
          g << "(($" << col[c] << " - " << num_exact(fig.offset) << ")*" << num_exact(fig.scale) << ")";
        else
          g << col[c];
        g << " with lines lw 1.5 title " << quoted(legend);
        first = false;
      }
      if (fig.has_hline && (panel == 0 || fig.hline_in_window))
        g << ", " << fig.hline << " with lines lw 2 dt 2 lc rgb 'red' title "
          << quoted(fig.hline_label);
      if (!bands.empty()) {  // legend entries of the shading
        bool any_slip = false, any_flight = false;
        for (const Band& b : bands) (b.slip ? any_slip : any_flight) = true;
        if (any_flight) g << ", keyentry with boxes fs solid 0.5 fc rgb '#a6c8f4' title 'flight (contact open)'";
        if (any_slip) g << ", keyentry with boxes fs solid 0.5 fc rgb '#f4a6a6' title 'slip'";
      }
      g << "\n";
    }
    g << "unset multiplot\nunset output\n";
  }
  std::vector<std::string> files;
  for (const auto& fig : figs) files.push_back(fig.file);
  pcsim::cli::run_plot_script(dir, g.str(), files, table.data ? &*table.data : nullptr);
  std::printf("pcsim plot: wrote");
  for (const auto& fig : figs) std::printf(" %s", (dir / fig.file).string().c_str());
  std::printf("\n  (gnuplot script: %s)\n", (dir / "plots.gp").string().c_str());
}

void setup(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "plot", "PNG figures (gnuplot) of a `pcsim run` or `pcsim steady` output directory (for "
              "the sieve theta, R_u, f*, x and y, and u with switching contacts; for any other "
              "model its coordinates, reactions and outputs; flights and slips of switching "
              "contacts shaded), or the response curves of a `pcsim response` directory");
  sub->add_option("dir", *dir, "the output directory of `pcsim run`, e.g. out/sieve_1995")
      ->required();
  sub->callback([dir]() { plot(*dir); });
}

const bool registered = pcsim::cli::register_command(20, &setup);

}  // namespace
