// The eigenvalue trace for `pcsim plot` (see plot_modes.hpp).
#include "modes/cli/plot_modes.hpp"

#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/plot_response.hpp"
#include "common/error.hpp"
#include "common/gnuplot.hpp"

namespace pcsim::cli {

namespace fs = std::filesystem;

bool is_modes_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::exists(dir / "modes_vary.json", ec) || fs::exists(dir / "modes.json", ec);
}

void plot_modes(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir / "modes_vary.json", ec))
    throw InputError(dir.string() + ": a pcsim modes output without a trace (modes.json and modes.csv are one "
                     "linearization; its numbers are the report): pcsim plot draws the eigenvalues of "
                     "`pcsim modes CASE --vary KEY=START:STOP:COUNT`");
  const nlohmann::json meta = read_plot_json(dir / "modes_vary.json", kMaxPlotJsonBytes);
  const TableShape shape = check_plot_table(dir / "modes_vary.csv", kMaxPlotResponseBytes, true);
  std::string key, cname;
  std::size_t tracks = 0;
  try {
    key = meta.at("key").get<std::string>();
    cname = meta.value("case", std::string());
    tracks = meta.at("tracks").size();
  } catch (const nlohmann::json::exception& e) {
    throw InputError((dir / "modes_vary.json").string() + ": not a complete pcsim modes trace (" + e.what() +
                     "); rerun pcsim modes --vary");
  }
  const std::size_t undamped = meta.value("undamped_tracks", nlohmann::json::array()).size();
  if (shape.header.size() != 2 + 2 * tracks + undamped || shape.header[0] != key)
    throw InputError((dir / "modes_vary.csv").string() + ": its columns do not match modes_vary.json (" +
                     std::to_string(tracks) + " tracks of " + key + "); rerun pcsim modes --vary");
  bool excitation = false;
  for (const auto& w : meta.value("excitation_frequency_rad_s", nlohmann::json::array())) excitation = excitation || !w.is_null();
  // A track whose imaginary part starts negative is the conjugate of another: drawn once.
  std::vector<std::size_t> drawn;
  for (std::size_t i = 0; i < tracks; ++i) {
    const auto& im = meta["tracks"][i].value("im", nlohmann::json::array());
    if (im.empty() || !im.front().is_number() || im.front().get<double>() >= 0) drawn.push_back(i);
  }
  static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
  std::ostringstream g;
  g << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n  set terminal pngcairo size 1000,900 font 'sans,10' noenhanced\n"
       "} else {\n  set terminal png size 1000,900 noenhanced\n}\n"
       "set datafile separator ','\nset datafile missing ''\nset grid\nset key outside right top\nset format y '%.4g'\n";
  g << "set output " << gnuplot_quoted("modes_vary.png") << "\n";
  g << "set multiplot layout 2,1 title " << gnuplot_quoted(cname + ": eigenvalues against " + key + ", paired by continuity; red dotted: stability crossings")
    << "\n";
  // The stability crossings the trace located, as vertical lines in both panels.
  int arrow = 1;
  for (const auto& x : meta.value("stability_crossings", nlohmann::json::array()))
    if (x.contains("value") && x["value"].is_number() && x.value("im", 0.0) >= 0)
      g << "set arrow " << arrow++ << " from " << x["value"].get<double>() << ", graph 0 to " << x["value"].get<double>()
        << ", graph 1 nohead dt 3 lc rgb '#d62728'\n";
  g << "set xlabel " << gnuplot_quoted(key) << "\nset ylabel 'Re lambda (1/s)'\n";
  g << "plot 0 with lines lw 2 dt 2 lc rgb 'black' title 'stability boundary Re = 0'";
  for (const std::size_t i : drawn)
    g << ", 'modes_vary.csv' every ::1 using 1:" << 3 + 2 * i << " with linespoints pt 7 ps 0.5 lw 1.5 lc rgb '"
      << colors[i % 8] << "' title " << gnuplot_quoted("track " + std::to_string(i + 1));
  g << "\nset ylabel 'Im lambda (rad/s), Im >= 0; dashed: undamped'\nplot ";
  if (excitation) g << "'modes_vary.csv' every ::1 using 1:2 with lines lw 2 dt 3 lc rgb 'black' title 'excitation frequency', ";
  for (std::size_t k = 0; k < drawn.size(); ++k) {
    const std::size_t i = drawn[k];
    g << (k ? ", " : "") << "'modes_vary.csv' every ::1 using 1:($" << 4 + 2 * i << " >= 0 ? $" << 4 + 2 * i
      << " : 1/0) with linespoints pt 7 ps 0.5 lw 1.5 lc rgb '" << colors[i % 8] << "' title "
      << gnuplot_quoted("track " + std::to_string(i + 1));
  }
  for (std::size_t i = 0; i < undamped; ++i)
    g << ", 'modes_vary.csv' every ::1 using 1:" << 3 + 2 * tracks + i << " with lines lw 1 dt 2 lc rgb '#7f7f7f' title "
      << gnuplot_quoted("undamped " + std::to_string(i + 1));
  g << "\nunset multiplot\nunset output\n";
  run_plot_script(dir, g.str(), {"modes_vary.png"});
}

}  // namespace pcsim::cli
