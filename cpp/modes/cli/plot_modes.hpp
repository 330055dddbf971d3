// The eigenvalue trace of a `pcsim modes --vary` output directory (pcsim plot DIR): real and
// imaginary parts of every track against the varied key, the stability boundary Re = 0 marked,
// and the excitation frequency drawn as a line when the model has one.
#pragma once

#include <filesystem>

namespace pcsim::cli {

/// True if dir holds a `pcsim modes` output (modes.json or modes_vary.json).
bool is_modes_dir(const std::filesystem::path& dir);

/// Draws dir/modes_vary.png with gnuplot (a trace); InputError for a directory without a trace
/// (a single linearization has nothing to draw against) or a malformed one.
void plot_modes(const std::filesystem::path& dir);

}  // namespace pcsim::cli
