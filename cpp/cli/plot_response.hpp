// Response curves of a `pcsim response` output directory (pcsim plot DIR): amplitudes of the
// coordinates and the client's margins against the varied key, stable branches solid and
// unstable ones dashed, resonances and folds marked.
#pragma once

#include <filesystem>

namespace pcsim::cli {

/// True if dir holds a `pcsim response` output (response.csv and response.json).
bool is_response_dir(const std::filesystem::path& dir);

/// Draws dir/amplitudes.png (and dir/margins.png when the response has the contact margin)
/// with gnuplot; throws pcsim::InputError for a malformed directory or a missing gnuplot.
void plot_response(const std::filesystem::path& dir);

}  // namespace pcsim::cli
