// Response curves for `pcsim plot` (see plot_response.hpp).
#include "cli/plot_response.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.hpp"

namespace pcsim::cli {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string f;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') f += '"', ++i;
      else if (c == '"') quoted = false;
      else f += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(f);
      f.clear();
    } else {
      f += c;
    }
  }
  out.push_back(f);
  return out;
}

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += (c == '\'') ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

bool is_response_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::exists(dir / "response.csv", ec) && fs::exists(dir / "response.json", ec);
}

void plot_response(const fs::path& dir) {
  const fs::path csv = dir / "response.csv";
  nlohmann::json meta;
  try {
    std::ifstream in(dir / "response.json");
    meta = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError((dir / "response.json").string() + ": not readable (" + e.what() + ")");
  }
  std::ifstream in(csv);
  std::string line;
  if (!std::getline(in, line)) throw InputError(csv.string() + ": empty");
  const auto header = split_csv(line);
  std::map<std::string, int> col;  // 1-based, as gnuplot counts
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = static_cast<int>(i) + 1;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line))
    if (!line.empty()) rows.push_back(split_csv(line));
  const std::string key = meta.value("key", std::string("p"));
  if (!col.count(key) || !col.count("stable")) throw InputError(csv.string() + ": no column '" + key + "' or 'stable'");
  // Coordinates to draw: the sieve's x, y, theta; otherwise every coordinate that moves.
  std::vector<std::string> coords;
  const bool sieve = meta.value("model", std::string()) == "sieve";
  for (const auto& h : header) {
    if (h.rfind("amplitude.", 0) != 0) continue;
    const std::string name = h.substr(10);
    if (sieve && name != "x" && name != "y" && name != "theta") continue;
    double amax = 0;
    for (const auto& r : rows) {
      const auto& f = r[col[h] - 1];
      if (!f.empty()) amax = std::max(amax, std::abs(std::stod(f)));
    }
    if (amax > 1e-15) coords.push_back(name);
  }
  if (coords.size() > 6) coords.resize(6);
  const bool any_unstable = meta.value("unstable_points", 0) > 0;
  double p_lo = INFINITY, p_hi = -INFINITY;
  for (const auto& r : rows)
    if (!r[col[key] - 1].empty()) p_lo = std::min(p_lo, std::stod(r[col[key] - 1])), p_hi = std::max(p_hi, std::stod(r[col[key] - 1]));
  // Labels near the right end are written to the left of their point.
  auto offset = [&](double at) { return at > 0.5 * (p_lo + p_hi) ? std::string("offset -14,-1") : std::string("offset 1,-1"); };
  std::ostringstream g;
  g << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
       "  set terminal pngcairo size 1000," << (260 * std::max<std::size_t>(coords.size(), 1) + 100)
    << " font 'sans,10' noenhanced\n} else {\n  set terminal png size 1000,"
    << (260 * std::max<std::size_t>(coords.size(), 1) + 100) << " noenhanced\n}\n"
       "set datafile separator ','\nset datafile missing ''\nset grid\nset key top left opaque box\n"
       "set format y '%.3g'\n";
  auto marks = [&](const std::string& coordinate, bool with_labels) {
    std::ostringstream m;
    int n = 1;
    for (const auto& f : meta["folds"])
      m << "set arrow " << n++ << " from " << f["at"].get<double>() << ", graph 0 to "
        << f["at"].get<double>() << ", graph 1 nohead dt 3 lc rgb '#808080'\n";
    int l = 1;
    if (with_labels)
      for (const auto& r : meta["resonances"]) {
        if (r["coordinate"].get<std::string>() != coordinate) continue;
        m << "set label " << l++ << " " << quoted("resonance " + num(r["at"].get<double>()))
          << " at " << r["at"].get<double>() << ", " << r["amplitude"].get<double>()
          << " point pt 7 ps 1.2 lc rgb 'red' " << offset(r["at"].get<double>()) << "\n";
      }
    return m.str();
  };
  auto curve = [&](int c, const std::string& title, const std::string& color) {
    const int s = col["stable"], p = col[key];
    std::ostringstream o;
    o << quoted(csv.string()) << " every ::1 using " << p << ":($" << s << "==1 ? $" << c
      << " : 1/0) with lines lw 2 lc rgb '" << color << "' title "
      << quoted(title + (any_unstable ? " (stable)" : ""));
    if (any_unstable)
      o << ", " << quoted(csv.string()) << " every ::1 using " << p << ":($" << s << "==0 ? $" << c
        << " : 1/0) with lines lw 2 dt 2 lc rgb '" << color << "' title " << quoted(title + " (unstable)");
    return o.str();
  };
  std::vector<std::string> files;
  g << "set output " << quoted((dir / "amplitudes.png").string()) << "\n";
  g << "set multiplot layout " << std::max<std::size_t>(coords.size(), 1) << ",1 title "
    << quoted(meta.value("case", std::string()) + ": steady-state amplitudes (half peak-to-peak) against " + key +
              (any_unstable ? "; dashed: unstable" : "; every orbit stable") +
              (meta["folds"].empty() ? "" : ", dotted lines: folds") +
              (meta["resonances"].empty() ? "" : ", red: resonances"))
    << "\n";
  for (const auto& q : coords) {
    g << "unset arrow\nunset label\n" << marks(q, true);
    g << "set xlabel " << quoted(key) << "\nset ylabel " << quoted("amplitude of " + q) << "\n";
    g << "plot " << curve(col["amplitude." + q], q, "#1f77b4") << "\n";
  }
  g << "unset multiplot\nunset output\n";
  files.push_back((dir / "amplitudes.png").string());
  if (col.count("contact_margin")) {
    g << "set terminal pngcairo size 1000,600 font 'sans,10' noenhanced\n";
    g << "set output " << quoted((dir / "margins.png").string()) << "\nunset arrow\nunset label\n"
      << "set key bottom left opaque box\n" << marks("", false);
    if (meta.contains("smallest_contact_margin"))
      g << "set label 1 " << quoted("smallest " + num(meta["smallest_contact_margin"]["margin"].get<double>()))
        << " at " << meta["smallest_contact_margin"]["at"].get<double>() << ", "
        << meta["smallest_contact_margin"]["margin"].get<double>() << " point pt 7 ps 1.2 lc rgb 'red' "
        << offset(meta["smallest_contact_margin"]["at"].get<double>()) << "\n";
    g << "set title " << quoted(meta.value("case", std::string()) +
                                ": margins of the working conditions in the steady state (contact: min R_u/(m2 g); rolling: 1 - max f*/f)")
      << "\nset xlabel " << quoted(key) << "\nset ylabel 'margin'\nset yrange [*:*]\n";
    g << "plot " << curve(col["contact_margin"], "contact margin", "#d62728");
    if (col.count("rolling_margin")) g << ", " << curve(col["rolling_margin"], "rolling margin", "#2ca02c");
    g << ", 0 with lines lw 1 lc rgb 'black' title 'violation'\nunset output\n";
    files.push_back((dir / "margins.png").string());
  }
  const fs::path script = dir / "plots.gp";
  {
    std::ofstream out(script);
    out << g.str();
    if (!out) throw InputError("cannot write " + script.string());
  }
  FILE* pipe = popen("gnuplot", "w");
  if (!pipe) throw InputError("cannot start gnuplot");
  std::fprintf(pipe, "load %s\n", quoted(script.string()).c_str());
  const int status = pclose(pipe);
  if (status != 0)
    throw std::runtime_error("gnuplot failed on " + script.string() + " (exit status " + std::to_string(status) + ")");
  std::printf("pcsim plot: wrote");
  for (const auto& f : files) std::printf(" %s", f.c_str());
  std::printf("\n  (gnuplot script: %s)\n", script.string().c_str());
}

}  // namespace pcsim::cli
