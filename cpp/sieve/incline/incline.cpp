// The sieve's incline study: theta free vs locked over design points, table and gnuplot figure.
#include "sieve/incline/incline.hpp"

#include <cstdlib>
#include <fstream>
#include <map>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "common/files.hpp"
#include "common/gnuplot.hpp"
#include "study/table.hpp"

namespace pcsim::sieve {

using namespace study;  // the sweep, its table and its runner

namespace {

const char* kLockKey = "constraints.lock_theta";

std::string diff_text(const std::map<std::string, double>& free_run,
                      const std::map<std::string, double>& locked, const std::string& name) {
  const auto f = free_run.find(name), l = locked.find(name);
  if (f == free_run.end() || l == locked.end()) return "";
  return csv_number(f->second - l->second);  // inf - inf is undefined: an empty field
}

std::string value_text(const std::map<std::string, double>& m, const std::string& name) {
  const auto it = m.find(name);
  return it == m.end() ? "" : csv_number(it->second);
}

/// gnuplot script: margins (top) and their free - locked differences (bottom) over the first
/// design key.
std::string gnuplot_script(const std::string& xkey, const std::string& case_name,
                           bool index_axis) {
  const std::string x = index_axis ? "0" : "1";  // column 0 = row number
  std::string s;
  s += "set terminal pngcairo noenhanced size 900,900 font 'sans,10'\n";
  s += "set output 'incline.png'\n";
  s += "set datafile separator ','\n";
  s += "set key autotitle columnhead\n";
  s += "set multiplot layout 2,1 title " +
       gnuplot_quoted("Influence of incline vibration (theta free vs locked), case " + case_name) + "\n";
  s += "set grid\n";
  s += "set xlabel " + gnuplot_quoted(index_axis ? std::string("design point") : xkey) + "\n";
  s += "set ylabel 'margin'\n";
  s += "set key below\n";
  s += "plot 'incline.csv' using " + x +
       ":(column('contact_margin_free')) with linespoints lw 2 pt 7 lc rgb '#1f77b4' title "
       "'contact, theta free', \\\n"
       "     '' using " + x +
       ":(column('contact_margin_locked')) with linespoints lw 2 pt 5 dt 2 lc rgb '#1f77b4' "
       "title 'contact, theta locked', \\\n"
       "     '' using " + x +
       ":(column('rolling_margin_free')) with linespoints lw 2 pt 7 lc rgb '#d62728' title "
       "'rolling, theta free', \\\n"
       "     '' using " + x +
       ":(column('rolling_margin_locked')) with linespoints lw 2 pt 5 dt 2 lc rgb '#d62728' "
       "title 'rolling, theta locked'\n";
  s += "set ylabel 'free - locked'\n";
  s += "plot 'incline.csv' using " + x +
       ":(column('contact_margin_diff')) with linespoints lw 2 pt 7 lc rgb '#1f77b4' title "
       "'contact margin', \\\n"
       "     '' using " + x +
       ":(column('rolling_margin_diff')) with linespoints lw 2 pt 7 lc rgb '#d62728' title "
       "'rolling margin'\n";
  s += "unset multiplot\n";
  return s;
}

}  // namespace

void check_incline_case(const sim::Case& base) {
  if (base.model->name() != "sieve" || !base.client)
    throw InputError(input_location(base.source) +
                     ": key 'model': expected the built-in model \"sieve\": the incline study "
                     "compares the sieve's desk with theta free and locked (constraints.lock_theta), "
                     "and the " + base.model->origin() + " has no such variant; use pcsim sweep "
                     "with --vary on a constraint switch instead");
}

sim::Axis default_incline_axis(const sim::Case& base) {
  const double a = base.table.at_path("parameters.a").value_or(0.5);
  const double r = base.table.at_path("parameters.r").value_or(0.1);
  const double half = a > r ? a - r : a;
  sim::Axis axis{"initial.s0", {}};
  for (int i = 0; i < 9; ++i) axis.texts.push_back(format_number(sim::round_decimal(-half + 2.0 * half * i / 8.0)));
  return axis;
}

const std::vector<std::string>& incline_columns() {
  static const std::vector<std::string> c = {
      "contact_margin_free", "contact_margin_locked", "contact_margin_diff",
      "rolling_margin_free", "rolling_margin_locked", "rolling_margin_diff",
      "amplitude_theta_free", "status", "error"};
  return c;
}

InclineReport run_incline_study(const sim::Case& base, const std::vector<sim::Axis>& design_axes,
                                const Runner& runner, const InclineOptions& options) {
  InclineReport report;
  check_incline_case(base);
  std::vector<sim::Axis> axes = design_axes;
  axes.push_back(sim::Axis{kLockKey, {"false", "true"}});
  const sim::Grid grid(axes);
  SweepOptions so;
  so.out_dir = options.out_dir;
  so.jobs = options.jobs;
  so.progress = options.progress;
  so.cluster = options.cluster;
  so.restart = options.restart;
  so.owner = "incline";
  report.sweep = run_sweep(base, grid, runner, so);
  report.points = grid.size() / 2;
  if (!report.sweep.ok) {
    report.ok = false;
    report.error = report.sweep.error;
    return report;
  }
  if (options.cluster && options.cluster->rank() != 0) return report;

  const auto sweep = read_csv(report.sweep.csv);
  if (!sweep || sweep->rows.size() < grid.size()) {
    report.ok = false;
    report.error = "cannot read back " + report.sweep.csv.string();
    return report;
  }
  const std::size_t nd = design_axes.size();
  const std::vector<std::string> summary_header(sweep->header.begin() + nd + 1,
                                                sweep->header.end());
  const std::size_t status_col = sweep->column(kStatusColumn).value();
  const std::size_t error_col = sweep->column(kErrorColumn).value();

  std::vector<std::string> header;
  for (const auto& a : design_axes) header.push_back(a.key);
  for (const auto& c : incline_columns()) header.push_back(c);
  std::string out = csv_line(header) + "\n";
  for (std::size_t d = 0; d < report.points; ++d) {
    const auto& free_row = sweep->rows[2 * d];
    const auto& locked_row = sweep->rows[2 * d + 1];
    const auto free_vals = numeric_fields(
        summary_header, std::vector<std::string>(free_row.begin() + nd + 1, free_row.end()));
    const auto locked_vals = numeric_fields(
        summary_header, std::vector<std::string>(locked_row.begin() + nd + 1, locked_row.end()));
    std::vector<std::string> row(free_row.begin(), free_row.begin() + nd);
    row.push_back(value_text(free_vals, "contact_margin"));
    row.push_back(value_text(locked_vals, "contact_margin"));
    row.push_back(diff_text(free_vals, locked_vals, "contact_margin"));
    row.push_back(value_text(free_vals, "rolling_margin"));
    row.push_back(value_text(locked_vals, "rolling_margin"));
    row.push_back(diff_text(free_vals, locked_vals, "rolling_margin"));
    row.push_back(value_text(free_vals, "amplitude.theta"));
    std::string error;
    if (free_row[status_col] != "ok") error += "theta free: " + free_row[error_col];
    if (locked_row[status_col] != "ok")
      error += (error.empty() ? "" : "; ") + std::string("theta locked: ") + locked_row[error_col];
    if (!error.empty()) ++report.failed;
    row.push_back(error.empty() ? "ok" : "error");
    row.push_back(error);
    out += csv_line(row) + "\n";
  }
  report.table = options.out_dir / "incline.csv";
  {
    std::ofstream f(report.table, std::ios::binary);
    f << out;
    if (!f) {
      report.ok = false;
      report.error = "cannot write " + report.table.string();
      return report;
    }
  }
  if (!options.plot) return report;
  const std::string xkey = design_axes.empty() ? "" : design_axes.front().key;
  const auto script = options.out_dir / "incline.gp";
  const std::string text = gnuplot_script(xkey, base.name, design_axes.size() != 1);
  int status = -1;
  std::string why;
  try {
    write_file_atomically(script, text);
    // No shell: gnuplot runs in the study's directory and reads the script on its input.
    status = run_gnuplot(options.out_dir, text, "gnuplot.log");
  } catch (const std::exception& e) {
    why = e.what();
  }
  if (status == 0) {
    report.plot = options.out_dir / "incline.png";
  } else {
    report.plot_error = (why.empty() ? "gnuplot failed (see " + (options.out_dir / "gnuplot.log").string() + ")"
                                     : "no figure: " + why) +
                        "; the table is in " + report.table.string();
  }
  return report;
}

}  // namespace pcsim::sieve
