// Case files for any model (TOML): loading, --set overrides, the model's keys and the common
// ones, defaults, validation, and the typed setup a run reads. The keys are the contracts of
// shared/design/architecture.md section 4 (the sieve) and model-files.md (any model).
#pragma once

#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/eigen_instances.hpp"
#include <toml++/toml.h>

#include "common/kernel.hpp"
#include "common/toml_guard.hpp"
#include "mech/status.hpp"
#include "ode/integrate.hpp"
#include "sim/keys.hpp"
#include "sim/model_source.hpp"

namespace pcsim::sim {

class Client;

/// The summary window of a run.
struct WindowSpec {
  int periods = 0;      ///< > 0: the last `periods` excitation periods
  double time = 0.0;    ///< > 0 (periods == 0): the last `time` seconds
};

/// The typed view of a validated case: what a run needs, as numbers. Every field comes from
/// the case's keys, their defaults from the key table (sim/keys.hpp); a Setup is built once,
/// when the case is loaded (Case::setup), never on its own.
struct Setup {
  ParameterValues parameters;           ///< every parameter, set or default
  Eigen::VectorXd q0, qd0;              ///< initial coordinates and velocities
  std::vector<std::string> active;      ///< active constraints, in the model's offer order
  Kernel kernel{};                      ///< solver.kernel
  mech::Form form{};                    ///< solver.form
  OdeMethod method{};                   ///< solver.method
  RadauOptions::LinearAlgebra linear_algebra{};  ///< solver.linear_algebra
  double rtol{}, atol{}, t_end{}, h0{};  ///< solver.rtol, .atol, .t_end (s), .h0 (s)
  long max_steps{};                     ///< solver.max_steps
  double dt{};                          ///< output.dt: the time-series interval, s
  bool npy{};                           ///< output.format = "npy": timeseries.npy, not .csv
  /// initial.from = "equilibrium": the run starts from the static equilibrium (run_case solves
  /// it from q0, slow coordinates held; docs/steady.md) instead of (q0, qd0).
  bool equilibrium_start{};
  WindowSpec window;                    ///< output.summary_periods or output.summary_time
  double period = std::numeric_limits<double>::quiet_NaN();  ///< excitation period, NaN if none
  /// [contact] (issue 12): switch the unilateral constraints (lift-off, impact, slip, stick).
  struct Contact {
    bool switching{};
    double zeno_time{};           ///< s, the accumulation rule (mech/contacts/switching.hpp)
    double flight_hmax{};         ///< s, largest step in flight or slip (0: none)
    long max_events{};
    std::string lcp_solver;
  } contact;
};

/// A validated case: the TOML table after overrides and defaults, the model it names and the
/// model's client (extra keys, verdicts and report; null for most models). Immutable once
/// loaded; copy it to vary a design.
struct Case {
  std::string name;                          ///< the case name (file stem unless set)
  std::filesystem::path source;              ///< the file it was loaded from ("" in memory)
  toml::table table;                         ///< every key, defaults filled in
  std::shared_ptr<const ModelSource> model;  ///< the model, with any added constraints
  std::shared_ptr<const Client> client;      ///< model-specific extras, or null
  /// The typed setup, built once when the case is loaded (and by retype after a direct edit of
  /// `table`).
  Setup setup;
};

/// One override in `--set KEY=VALUE` form: a dotted key and the value as text.
using Override = std::pair<std::string, std::string>;

/// The largest case file pcsim reads.
inline constexpr std::size_t kMaxCaseBytes = 16u << 20;

/// Splits "KEY=VALUE"; throws pcsim::InputError if there is no '='.
Override parse_override(const std::string& text);

/// The overrides of a command line: each --set KEY=VALUE, then each --constraint NAME=EXPR as
/// constraints.added.NAME=EXPR (an added holonomic constraint).
std::vector<Override> command_line_overrides(const std::vector<std::string>& sets,
                                             const std::vector<std::string>& added_constraints);

/// The longest case name, in bytes (a case name is a file name: see check_case_name).
inline constexpr std::size_t kMaxCaseNameBytes = 128;

/// "" if `name` can be a case name, else what is wrong with it. A case name becomes the name
/// of its output directory (out/<name>, out/<name>-sweep, ...), so it is a file name, not a
/// path: not empty, at most kMaxCaseNameBytes bytes of valid UTF-8, not starting with '.'
/// (hidden names are pcsim's own lock and staging files, and . and .. are not names), and
/// without '/', '\\' or control characters.
std::string case_name_problem(const std::string& name);

/// `base` + `suffix` (e.g. "-optimized"), with base shortened at a character boundary so the
/// result is a valid case name of at most kMaxCaseNameBytes bytes.
std::string derived_case_name(const std::string& base, const std::string& suffix);

/// Loads the case file, resolves its model (a built-in name, a model file relative to the case
/// file, or an inline [model] table), applies the overrides in order, fills the defaults and
/// validates every key. Throws pcsim::InputError naming the file, the key and what was expected.
Case load_case(const std::filesystem::path& file, const std::vector<Override>& overrides = {});

/// The same from the text of a case file (`file` names it in messages and anchors model paths).
Case load_case_text(const std::string& text, const std::filesystem::path& file,
                    const std::vector<Override>& overrides = {});

/// The same from a table in memory (`source` names it in messages and anchors model paths).
Case case_from_table(toml::table table, const std::filesystem::path& source,
                     const std::vector<Override>& overrides = {});

/// Applies one override with the same validation; a rejected override leaves the case as it was.
void set_value(Case& c, const Override& o);

/// The schema of the case: every key it may hold (common keys, the model's, the client's).
std::vector<KeySpec> case_keys(const Case& c);

/// True if `dotted_key` names a numeric (number or integer) key of this case.
bool is_numeric_key(const Case& c, const std::string& dotted_key);
/// True if `dotted_key` names an integer key of this case.
bool is_integer_key(const Case& c, const std::string& dotted_key);

/// The case as TOML text that load_case reads back to an equal case, wherever it is written (a
/// model file is named by its absolute path). `title` is the comment on the first line.
std::string to_toml(const Case& c, const std::string& title = "pcsim case");

/// Rebuilds c.setup from c.table after the table was edited in place (the client may adjust it,
/// e.g. the sieve's s0). The case must have been valid before the edit and stay valid.
void retype(Case& c);

}  // namespace pcsim::sim
