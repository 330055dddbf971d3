// Response curves of a `pcsim response` output directory (pcsim plot DIR): amplitudes of the
// coordinates and the client's margins against the varied key, stable branches solid and
// unstable ones dashed, resonances and folds marked.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pcsim::cli {

/// What pcsim plot reads, at most: a JSON file (summary.json, steady.json, response.json) and
/// response.csv 64 MiB each, timeseries.csv and events.csv 1 GiB each. Larger files, and files
/// that are not regular files (a link to /dev/zero, a FIFO), are refused (exit 2) before any
/// is read.
inline constexpr std::uint64_t kMaxPlotJsonBytes = std::uint64_t{64} << 20;
inline constexpr std::uint64_t kMaxPlotResponseBytes = std::uint64_t{64} << 20;
inline constexpr std::uint64_t kMaxPlotTableBytes = std::uint64_t{1} << 30;

/// The JSON file parsed; InputError naming the file if it is not a regular file of at most
/// max_bytes or not JSON.
nlohmann::json read_plot_json(const std::filesystem::path& file, std::uint64_t max_bytes);

/// A CSV table as pcsim writes it, checked whole without keeping it in memory: the header's
/// fields and the number of rows. InputError naming the file if it is not a regular file of at
/// most max_bytes, or is half-written: no header, a row with another number of fields than the
/// header, a last line without its line break, or (need_rows) no row at all.
struct TableShape {
  std::vector<std::string> header;
  std::size_t rows = 0;
};
TableShape check_plot_table(const std::filesystem::path& file, std::uint64_t max_bytes, bool need_rows);

/// Runs `script` with gnuplot in `dir` (its file names are relative to dir; no path enters a
/// script). Each figure of `figures` (file names in dir, each set by a line
/// `set output 'NAME'`) is drawn under a temporary name `.NAME.part<pid>` and replaces the
/// figure only when gnuplot succeeds; otherwise the temporaries are removed and
/// std::runtime_error is thrown, so a failed plot leaves no figure behind. The script is kept as
/// dir/plots.gp (rerun it with `cd DIR && gnuplot plots.gp`).
/// `data`, when given, is a data file the script reads (by its quoted name): written under a
/// temporary name for gnuplot and moved into dir with the figures, or removed with them.
struct PlotData {
  std::string name, content;
};
void run_plot_script(const std::filesystem::path& dir, const std::string& script,
                     const std::vector<std::string>& figures, const PlotData* data = nullptr);

/// True if dir holds a `pcsim response` output (response.csv and response.json).
bool is_response_dir(const std::filesystem::path& dir);

/// Draws dir/amplitudes.png (and dir/margins.png when the response has the contact margin)
/// with gnuplot; throws pcsim::InputError for a malformed directory or a missing gnuplot.
void plot_response(const std::filesystem::path& dir);

}  // namespace pcsim::cli
