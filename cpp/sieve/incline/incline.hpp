// `pcsim study incline`: the paper's question, how the desk's incline vibration theta changes
// the roller's working conditions. Every design point runs twice, theta free and theta locked.
// The sieve's study, built on the generic sweep (cpp/study/sweep.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sim/case.hpp"
#include "study/cluster.hpp"
#include "study/sweep.hpp"
#include "sim/vary.hpp"

namespace pcsim::sieve {

/// The default design axis: the roller's initial position initial.s0 across the deck, from
/// -(a - r) to +(a - r) in 9 points. The model fixes no deck length; the desk's outermost
/// attachment is the horizontal spring at xi = a (0.5 m), so the deck is taken as
/// [-a, a] and the roller (radius r) kept on it. If a <= r, the range is [-a, a].
sim::Axis default_incline_axis(const sim::Case& base);

/// Throws pcsim::InputError unless the case's model is the built-in sieve (the study needs its
/// constraints.lock_theta and margins), naming the key and the reason.
void check_incline_case(const sim::Case& base);

/// The columns of incline.csv after the design keys.
const std::vector<std::string>& incline_columns();

struct InclineOptions {
  std::filesystem::path out_dir = "out/incline";
  unsigned jobs = 0;                  ///< threads per rank; 0 = all cores
  bool progress = false;              ///< progress bar on stderr
  const study::Cluster* cluster = nullptr;   ///< MPI ranks; null = this process alone
  bool plot = true;                   ///< run gnuplot for incline.png
  bool restart = false;               ///< see SweepOptions::restart
};

struct InclineReport {
  bool ok = true;
  std::string error;                  ///< why it failed (I/O); points that fail are rows
  study::SweepReport sweep;                  ///< the underlying sweep (out_dir/sweep.csv)
  std::filesystem::path table;        ///< out_dir/incline.csv
  std::filesystem::path plot;         ///< out_dir/incline.png ("" if not drawn)
  std::string plot_error;             ///< why the plot was not drawn, if it was not
  std::size_t points = 0;             ///< design points
  std::size_t failed = 0;             ///< design points with a failed run
};

/// Sweeps design_axes x constraints.lock_theta in {false, true} into out_dir/sweep.csv
/// (resumable like any sweep), then writes out_dir/incline.csv: per design point, the contact
/// margin min R_u/(m2 g) and the rolling margin 1 - max f*/f with theta free and locked, their
/// differences (free - locked: the influence of incline vibration; negative means theta
/// makes that working condition worse) and the theta amplitude; and, with plot, the gnuplot
/// script incline.gp and its figure incline.png (x axis: the first design key). Rank 0
/// writes incline.csv and the figure.
InclineReport run_incline_study(const sim::Case& base, const std::vector<sim::Axis>& design_axes,
                                const study::Runner& runner, const InclineOptions& options);

}  // namespace pcsim::sieve
