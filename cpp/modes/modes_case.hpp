// `pcsim modes` for a case: the reference (the case's initial state if it rests, its static
// equilibrium with initial.from = "equilibrium", or a steady motion with [modes] cyclic), the
// excitation (off: averaged over one period; or held at a phase), the linearization on the
// tangent space of the constraints (modes/linearize.hpp), and its outputs: the report,
// modes.json and modes.csv; and the eigenvalues traced over a parameter (--vary), paired by
// continuity: modes_vary.csv and modes_vary.json.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "modes/linearize.hpp"
#include "sim/case.hpp"

namespace pcsim::modes {

struct ModesOptions {
  /// Where to write (nullopt: nowhere); the directory is written as a whole (common/files.hpp),
  /// owned by `pcsim modes`.
  std::optional<std::filesystem::path> out_dir;
  /// Overrides of the case's [modes] keys from the command line ("" / not given: the case's).
  std::optional<std::string> excitation;
  std::optional<std::vector<std::string>> cyclic;
};

/// The reference of a case, resolved: what linearize() gets, and how it was chosen.
struct Reference {
  LinearizeInput input;
  std::shared_ptr<const mech::Model> model;
  std::string source;            ///< "initial state", "static equilibrium"
  std::string excitation;        ///< "off", "phase", "none"
  double phase = 0;              ///< rad, when held at a phase
  double period = 0;             ///< s, NaN without excitation
  std::string excitation_text;   ///< what the choice means, for the report
  std::vector<std::string> cyclic;
};

/// Resolves the reference of a case; throws pcsim::InputError for what cannot be done (a model
/// without exact tangents, a bad [modes] key, cyclic coordinates with initial.from =
/// "equilibrium") and pcsim::NumericalError when the static equilibrium is not found.
Reference case_reference(const sim::Case& c, const ModesOptions& options);

/// Linearizes the case about its reference and checks it: pcsim::InputError (exit 2) when the
/// reference is not a rest state or steady motion (the residual and the coordinates that move)
/// or a cyclic coordinate appears in the equations; pcsim::NumericalError (exit 3) when the
/// linearization does not exist there. Returns modes.json's content.
nlohmann::json case_modes(const sim::Case& c, const ModesOptions& options, Linearization* out = nullptr);

/// `pcsim modes CASE`: case_modes, written as modes.json and modes.csv (when out_dir is set).
nlohmann::json modes_case(const sim::Case& c, const ModesOptions& options);

/// modes.csv: one row per mode (pairs once).
std::string modes_csv(const nlohmann::json& j);

/// The engineer's report.
std::string modes_report(const sim::Case& c, const nlohmann::json& j);

/// --vary KEY=START:STOP:COUNT.
struct VarySpec {
  std::string key;
  double start = 0, stop = 0;
  int count = 0;
};
/// Parses KEY=START:STOP:COUNT; throws pcsim::InputError naming what is wrong.
VarySpec parse_vary(const std::string& text);

/// Pairs the eigenvalues of the next step with the tracks (the current values and a predicted
/// next value per track): the assignment of least total distance |predicted − λ| (Hungarian
/// method). Returns, per track, the index into `next`.
std::vector<int> pair_by_continuity(const std::vector<std::complex<double>>& predicted,
                                    const std::vector<std::complex<double>>& next);
/// The same with the eigenvectors (unit columns): the cost of a pair is
/// |predicted − λ| + scale_i (1 − |u_i·v|), scale_i the track's change over its last step, so
/// that where eigenvalues come close (a crossing, a cluster of zero eigenvalues) the mode shapes
/// decide.
std::vector<int> pair_by_continuity(const std::vector<std::complex<double>>& predicted,
                                    const std::vector<std::complex<double>>& next,
                                    const Eigen::MatrixXcd& previous_vectors, const Eigen::MatrixXcd& next_vectors,
                                    const std::vector<double>& scales);

/// Traces the eigenvalues over the key; writes modes_vary.csv and modes_vary.json (when
/// out_dir is set) and returns modes_vary.json's content. A step at which the reference is not
/// a rest state or the linearization does not exist fails the whole trace (InputError or
/// NumericalError naming the key's value), and nothing is written.
nlohmann::json modes_vary(const sim::Case& c, const ModesOptions& options, const VarySpec& vary);

/// The report of a trace.
std::string vary_report(const nlohmann::json& j);

}  // namespace pcsim::modes
