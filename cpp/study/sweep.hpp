// The sweep engine: every point of a grid run through an injectable runner, in parallel
// threads (and MPI ranks), into a resumable sweep.csv in grid order.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/case.hpp"
#include "sim/result.hpp"
#include "study/cluster.hpp"
#include "sim/vary.hpp"

namespace pcsim::study {

/// Runs one design point and returns its result; may throw (the point's row then records the
/// error). Must be safe to call from several threads at once.
using Runner = std::function<sim::RunResult(const sim::Case&)>;

/// sim::run_case writing no files: the runner of the pcsim commands.
Runner case_runner();

struct SweepOptions {
  std::filesystem::path out_dir = "out/sweep";  ///< sweep.csv is written here
  unsigned jobs = 0;                            ///< threads per rank; 0 = all cores
  bool progress = false;                        ///< progress bar on stderr (rank 0)
  const Cluster* cluster = nullptr;             ///< MPI ranks to share the points; null = alone
  /// An existing sweep.csv computed for another case (its journal key differs): false refuses
  /// the sweep naming what changed; true discards the old rows and computes every point.
  bool restart = false;
  /// The command that owns out_dir (its marker, common/files.hpp): "sweep", or "incline" for
  /// the incline study's sweep. A directory of another command is refused.
  std::string owner = "sweep";
};

struct SweepReport {
  bool ok = true;            ///< false: `error` says why (I/O, or sweep.csv of another sweep)
  std::string error;
  std::filesystem::path csv;   ///< out_dir/sweep.csv
  std::size_t points = 0;      ///< grid size
  std::size_t skipped = 0;     ///< already in sweep.csv from an earlier run
  std::size_t ran = 0;         ///< run now
  std::size_t failed = 0;      ///< rows of the final table with status "error"
  std::size_t dropped = 0;     ///< torn or malformed lines dropped from an earlier sweep.csv
  std::size_t foreign = 0;     ///< earlier rows not on this grid, kept after the grid rows
};

/// sweep.csv's header: the axis keys, summary_columns(base), status, error.
std::vector<std::string> sweep_header(const sim::Case& base, const sim::Grid& grid);

/// The fields of grid point i's row: its values, the flattened summary of runner(point case),
/// "ok" and ""; or, if setting the values or the run throws, empty summary fields, "error" and
/// the reason.
std::vector<std::string> sweep_row(const sim::Case& base, const sim::Grid& grid, std::size_t i,
                                   const Runner& runner);

/// The journal key of a sweep: the pcsim version, the model's fingerprint, the varied keys and
/// the complete effective case (after overrides) without the varied keys. Rows in sweep.csv are
/// reused only while out_dir/sweep.key holds the same text.
std::string sweep_key(const sim::Case& base, const sim::Grid& grid);

/// Runs every point of `grid` not yet in out_dir/sweep.csv and leaves sweep.csv holding the
/// header and one row per grid point in grid order (then any earlier rows not on this grid).
///
/// File protocol (crash safety): an existing sweep.csv with the same header is read; complete
/// lines (ending in '\n') with the right number of fields are kept, a torn last line or a
/// malformed line is dropped; the kept lines are written back via a temporary file and rename.
/// Each finished point is then appended as one complete line with write + fsync, so an
/// interruption loses only the points in flight and at worst leaves a torn last line, which
/// the next run drops. At the end the whole table is rewritten in grid order via temporary
/// file + fsync + rename, so sweep.csv is never seen half-written.
///
/// Reuse is keyed (sweep_key, in out_dir/sweep.key): rows of an earlier sweep of another case,
/// model or pcsim version are never taken as current; the sweep is refused, naming the first
/// differences, or (options.restart) started afresh. A second sweep into the same directory
/// while one runs is refused (flock on out_dir/.sweep.lock).
///
/// With a multi-rank cluster, rank 0 owns the file; the pending points are dealt out
/// round-robin (pending[k] goes to rank k mod size), every rank runs its share with `jobs`
/// threads and sends finished rows to rank 0. Every rank returns the same report.
SweepReport run_sweep(const sim::Case& base, const sim::Grid& grid, const Runner& runner,
                      const SweepOptions& options);

}  // namespace pcsim::study
