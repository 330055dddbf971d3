// Response curves for `pcsim plot` (see plot_response.hpp).
#include "cli/plot_response.hpp"

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "common/gnuplot.hpp"
#include "sim/client.hpp"

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

std::string quoted(const std::string& s) { return gnuplot_quoted(s); }

/// Opens a file for reading if it is a regular file of at most max_bytes; InputError otherwise.
/// O_NONBLOCK: opening a FIFO must not wait for a writer.
int open_limited(const fs::path& file, std::uint64_t max_bytes) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(errno_message("cannot read", file));
  struct stat st{};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(file.string() + ": not a regular file (pcsim plot reads only the files pcsim wrote)");
  }
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    throw InputError(file.string() + ": " + std::to_string(st.st_size) + " bytes, more than pcsim plot reads (" +
                     std::to_string(max_bytes >> 20) + " MiB)");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

/// Reads at most max_bytes of the open file (a file that grows while read is cut there).
std::string read_limited(int fd, const fs::path& file, std::uint64_t max_bytes) {
  std::string text;
  char buf[65536];
  while (text.size() <= max_bytes) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string msg = errno_message("cannot read", file);
      ::close(fd);
      throw InputError(msg);
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  if (text.size() > max_bytes) throw InputError(file.string() + ": grew beyond " + std::to_string(max_bytes >> 20) + " MiB while read");
  return text;
}

/// Number of fields of a CSV line (commas outside double quotes, plus one).
std::size_t field_count(const std::string& line) {
  std::size_t n = 1;
  bool q = false;
  for (char c : line) {
    if (c == '"') q = !q;
    else if (c == ',' && !q) ++n;
  }
  return n;
}

std::string half_written(const fs::path& file, const std::string& what) {
  return file.string() + ": " + what + "; the directory looks half-written (a run that was stopped, "
         "or a copy in progress): rerun the command that wrote it";
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

nlohmann::json read_plot_json(const fs::path& file, std::uint64_t max_bytes) {
  const std::string text = read_limited(open_limited(file, max_bytes), file, max_bytes);
  try {
    return nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw InputError(half_written(file, std::string("not readable JSON (") + e.what() + ")"));
  }
}

TableShape check_plot_table(const fs::path& file, std::uint64_t max_bytes, bool need_rows) {
  const int fd = open_limited(file, max_bytes);
  TableShape shape;
  std::string line;
  bool have_header = false;
  std::size_t line_no = 0;
  std::uint64_t total = 0;
  bool partial = false;  // bytes after the last line break
  char buf[65536];
  auto fail = [&](const std::string& what) {
    ::close(fd);
    throw InputError(half_written(file, what));
  };
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(std::string("cannot read: ") + std::strerror(errno));
    if (n == 0) break;
    total += static_cast<std::uint64_t>(n);
    if (total > max_bytes) fail("grew beyond " + std::to_string(max_bytes >> 20) + " MiB while read");
    for (ssize_t i = 0; i < n; ++i) {
      partial = buf[i] != '\n';
      if (buf[i] != '\n') {
        if (!have_header && line.size() > (1u << 20)) fail("a header line longer than 1 MiB");
        if (have_header) {  // rows: only the field count matters
          if (buf[i] == ',' || buf[i] == '"') line += buf[i];
        } else {
          line += buf[i];
        }
        continue;
      }
      ++line_no;
      if (!have_header) {
        shape.header = split_csv(line);
        have_header = true;
      } else if (field_count(line) != shape.header.size()) {
        fail("line " + std::to_string(line_no) + " has " +
             counted(static_cast<long long>(field_count(line)), "field") + ", the header " +
             std::to_string(shape.header.size()));
      } else {
        ++shape.rows;
      }
      line.clear();
    }
  }
  ::close(fd);
  if (!have_header && !partial) throw InputError(half_written(file, "empty"));
  if (partial || !have_header) throw InputError(half_written(file, "its last line is cut off (no line break)"));
  if (need_rows && shape.rows == 0) throw InputError(half_written(file, "no rows after the header"));
  return shape;
}

std::string temporary_name(const std::string& figure) {
  return "." + figure + ".part" + std::to_string(::getpid());
}

void run_plot_script(const fs::path& dir, const std::string& user_script,
                     const std::vector<std::string>& figures, const PlotData* data) {
  std::string script = user_script;
  std::vector<std::string> outputs = figures;  // what the run moves into dir
  for (const auto& f : figures) {
    const std::string line = "set output " + gnuplot_quoted(f) + "\n";
    const auto at = script.find(line);
    if (at == std::string::npos) throw std::logic_error("plot script without the output " + f);
    script.replace(at, line.size(), "set output " + gnuplot_quoted(temporary_name(f)) + "\n");
  }
  if (!find_on_path("gnuplot"))
    throw InputError("pcsim plot needs gnuplot, which is not on PATH: install it (Debian: "
                     "apt-get install gnuplot-nox, or run scripts/install-deps.sh)");
  if (data) {
    const std::string from = gnuplot_quoted(data->name), to = gnuplot_quoted(temporary_name(data->name));
    for (auto at = script.find(from); at != std::string::npos; at = script.find(from, at + to.size()))
      script.replace(at, from.size(), to);
    outputs.push_back(data->name);
  }
  auto remove_temporaries = [&] {
    std::error_code ec;
    for (const auto& f : outputs) fs::remove(dir / temporary_name(f), ec);
  };
  if (data) write_file_atomically(dir / temporary_name(data->name), data->content);
  int status = -1;
  try {
    status = run_gnuplot(dir, script);
  } catch (...) {
    remove_temporaries();
    throw;
  }
  if (status != 0) {
    remove_temporaries();
    throw std::runtime_error("gnuplot failed (exit status " + std::to_string(status) +
                             ", its messages above) on the files of " + dir.string() +
                             "; no figure was written");
  }
  for (const auto& f : outputs)
    if (std::rename((dir / temporary_name(f)).c_str(), (dir / f).c_str()) != 0) {
      const std::string msg = errno_message("cannot move the figure into", dir / f);
      remove_temporaries();
      throw IoError(msg);
    }
  write_file_atomically(dir / "plots.gp", user_script);
}

namespace {
void draw_response(const fs::path& dir);
}

bool is_response_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::exists(dir / "response.csv", ec) && fs::exists(dir / "response.json", ec);
}

void plot_response(const fs::path& dir) {
  try {
    draw_response(dir);
  } catch (const nlohmann::json::exception& e) {
    throw InputError((dir / "response.json").string() + ": not a complete pcsim response (" + e.what() +
                     "); rerun pcsim response");
  } catch (const std::invalid_argument& e) {
    throw InputError((dir / "response.csv").string() + ": a field that is not a number; rerun pcsim response");
  } catch (const std::out_of_range& e) {
    throw InputError((dir / "response.csv").string() + ": a number out of range; rerun pcsim response");
  }
}

namespace {

void draw_response(const fs::path& dir) {
  const fs::path csv = dir / "response.csv";
  nlohmann::json meta = read_plot_json(dir / "response.json", kMaxPlotJsonBytes);
  const TableShape shape = check_plot_table(csv, kMaxPlotResponseBytes, true);
  std::ifstream in(csv);
  std::string line;
  if (!std::getline(in, line)) throw InputError(csv.string() + ": empty");
  const auto header = split_csv(line);
  if (header != shape.header) throw InputError(csv.string() + ": changed while read");
  std::map<std::string, int> col;  // 1-based, as gnuplot counts
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = static_cast<int>(i) + 1;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line))
    if (!line.empty()) {
      rows.push_back(split_csv(line));
      if (rows.back().size() != header.size()) throw InputError(csv.string() + ": changed while read");
    }
  const std::string key = meta.value("key", std::string("p"));
  if (!col.count(key) || !col.count("stable")) throw InputError(csv.string() + ": no column '" + key + "' or 'stable'");
  // Coordinates to draw: those the model's client names (the sieve: x, y, theta), of them or
  // of all every coordinate that moves.
  std::vector<std::string> coords, chosen;
  if (const auto client = sim::find_client(meta.value("model", std::string())))
    chosen = client->response_coordinates();
  for (const auto& h : header) {
    if (h.rfind("amplitude.", 0) != 0) continue;
    const std::string name = h.substr(10);
    if (!chosen.empty() && std::find(chosen.begin(), chosen.end(), name) == chosen.end()) continue;
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
    o << "'response.csv' every ::1 using " << p << ":($" << s << "==1 ? $" << c
      << " : 1/0) with lines lw 2 lc rgb '" << color << "' title "
      << quoted(title + (any_unstable ? " (stable)" : ""));
    if (any_unstable)
      o << ", 'response.csv' every ::1 using " << p << ":($" << s << "==0 ? $" << c
        << " : 1/0) with lines lw 2 dt 2 lc rgb '" << color << "' title " << quoted(title + " (unstable)");
    return o.str();
  };
  std::vector<std::string> files;
  g << "set output " << quoted("amplitudes.png") << "\n";
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
  files.push_back("amplitudes.png");
  if (col.count("contact_margin")) {
    g << "set terminal pngcairo size 1000,600 font 'sans,10' noenhanced\n";
    g << "set output " << quoted("margins.png") << "\nunset arrow\nunset label\n"
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
    files.push_back("margins.png");
  }
  run_plot_script(dir, g.str(), files);
  std::printf("pcsim plot: wrote");
  for (const auto& f : files) std::printf(" %s", (dir / f).string().c_str());
  std::printf("\n  (gnuplot script: %s)\n", (dir / "plots.gp").string().c_str());
}

}  // namespace

}  // namespace pcsim::cli
