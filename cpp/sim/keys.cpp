// The key table of the common case keys (README, "Case files"; model-files.md).
#include "sim/keys.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace pcsim::sim {

namespace {

using Type = KeySpec::Type;

KeySpec key(std::string section, std::string name, Type type, std::string meaning) {
  KeySpec k;
  k.section = std::move(section);
  k.name = std::move(name);
  k.type = type;
  k.meaning = std::move(meaning);
  return k;
}

KeySpec number(std::string section, std::string name, std::string unit, std::string meaning,
               std::optional<double> def, double min, bool min_excl, double max = INFINITY) {
  KeySpec k = key(std::move(section), std::move(name), Type::number, std::move(meaning));
  k.unit = std::move(unit);
  k.number_default = def;
  k.min = min;
  k.min_exclusive = min_excl;
  k.max = max;
  return k;
}

/// An integer count: its default is the Setup's, not written into the case table.
KeySpec count(std::string section, std::string name, std::string meaning, double def, double min,
              double max) {
  KeySpec k = key(std::move(section), std::move(name), Type::integer, std::move(meaning));
  k.number_default = def;
  k.fill_default = false;
  k.min = min;
  k.max = max;
  return k;
}

KeySpec choice(std::string section, std::string name, std::string meaning,
               std::vector<std::string> choices, std::string def) {
  KeySpec k = key(std::move(section), std::move(name), Type::string, std::move(meaning));
  k.choices = std::move(choices);
  k.string_default = std::move(def);
  return k;
}

KeySpec flag(std::string section, std::string name, std::string meaning, bool def) {
  KeySpec k = key(std::move(section), std::move(name), Type::boolean, std::move(meaning));
  k.bool_default = def;
  return k;
}

/// The largest integer a case may give for a count (summary periods): larger values are
/// refused instead of wrapping around in an int.
constexpr double kMaxCount = 1e6;
/// The largest solver.max_steps and contact.max_events.
constexpr double kMaxSteps = 1e9;

std::vector<KeySpec> table() {
  std::vector<KeySpec> keys;
  keys.push_back(key("", "name", Type::string, "the case name"));
  {
    KeySpec from = choice(
        "initial", "from",
        "where the run starts: \"state\", the [initial] values as given (the default), or "
        "\"equilibrium\", the static equilibrium under the forces at rest averaged over an "
        "excitation period, slow coordinates held at their [initial] values (docs/steady.md)",
        {"state", "equilibrium"}, "state");
    from.fill_default = false;
    keys.push_back(from);
  }
  keys.push_back(choice("solver", "kernel", "the kernel implementation", {"fortran", "cpp"},
                        "fortran"));
  keys.push_back(choice("solver", "form", "the formulation", {"ode", "dae"}, "ode"));
  keys.push_back(choice("solver", "method",
                        "the integrator: Radau IIA, the explicit Dormand-Prince 8(5,3) pair, or "
                        "auto (explicit until its stiffness test fires, then Radau)",
                        {"radau", "explicit", "auto"}, "auto"));
  keys.push_back(choice("solver", "linear_algebra",
                        "Radau's linear algebra: the project's small-matrix LU on the reduced "
                        "(second-order) systems where it is faster than LAPACK (auto), always the "
                        "own LU, or LAPACK's LU on the full system; it changes nothing else",
                        {"auto", "own", "lapack"}, "auto"));
  // The default tolerances (README, "Case files"): a 1 m pendulum released horizontally
  // (IFToMM A01) ends 10 s later within 1.1e-7 m of the exact motion with them (1.8e-5 m with
  // the former 1e-6 / 1e-8, whose error showed in the 5th of the report's 6 printed digits).
  // The smallest rtol: below it rounding dominates (README, "Limits and failure behaviour").
  // The largest: the reports print 3 to 6 significant digits and their verdicts compare
  // margins to 3; a relative error per step above 1e-3 cannot give even the third digit.
  keys.push_back(number("solver", "rtol", "",
                        "relative tolerance; below 1e-13 the error estimates are dominated by the "
                        "rounding of double precision, above 1e-3 no printed digit of the report "
                        "would be reliable",
                        1e-8, 1e-13, false, 1e-3));
  // The largest atol in any unit: a run checks it against its own coordinates' magnitudes as
  // well (run.cpp, tolerance_check).
  keys.push_back(number("solver", "atol", "",
                        "absolute tolerance, in the units of each coordinate and velocity; at "
                        "most 1e-3, and a run whose coordinates move by less than 100 atol is "
                        "reported unreliable (exit 3)",
                        1e-10, 0.0, true, 1e-3));
  keys.push_back(number("solver", "t_end", "s",
                        "end time, s; at least 1e-9 s, so the run and its summary window are more "
                        "than a rounding error long",
                        10.0, 1e-9, false));
  keys.push_back(number("solver", "h0", "s", "initial step, s (0: automatic)", 0.0, 0.0, false));
  keys.push_back(count("solver", "max_steps",
                       "the most integration steps a run may take before it fails with 'too many "
                       "steps' (and the time reached)",
                       1e6, 1, kMaxSteps));
  keys.push_back(number("output", "dt", "s", "output interval, s", 1e-3, 0.0, true));
  // Issue 23: a binary time series for large runs (README, "Output files").
  keys.push_back(choice("output", "format",
                        "pcsim run's time-series file: timeseries.csv (shortest round-trip decimals) or "
                        "timeseries.npy (NumPy's array format: each value's 8 bytes, for large runs "
                        "read with numpy.load; pcsim steady writes its one period the same way, and "
                        "pcsim plot and animate read either)",
                        {"csv", "npy"}, "csv"));
  {
    // Only for models with an excitation period (the schema leaves it out for others).
    KeySpec periods =
        count("output", "summary_periods", "excitation periods in the summary window", 5, 1,
              kMaxCount);
    periods.default_text = "5 (models with an excitation period)";
    keys.push_back(periods);
  }
  {
    KeySpec time = number("output", "summary_time", "s",
                          "length of the summary window, s (from t_end back)", std::nullopt, 0.0,
                          true);
    time.default_text = "the whole run";
    keys.push_back(time);
  }
  // [contact] (issue 12): switching the unilateral constraints.
  keys.push_back(flag("contact", "switching",
                      "switch the unilateral constraints: lift-off, flight, impact, slip and "
                      "sticking again (docs/switching.md); false keeps every constraint imposed, "
                      "as the paper does",
                      false));
  keys.push_back(number("contact", "zeno_time", "s",
                        "s; an impact whose rebound would fly shorter than this closes the "
                        "contact (accumulation of impacts)",
                        1e-6, 0.0, true));
  {
    KeySpec hmax = number("contact", "flight_hmax", "s",
                          "s; the largest step while a contact flies or slides (default: a 16th "
                          "of the excitation period, or none)",
                          std::nullopt, 0.0, true);
    hmax.default_text = "a 16th of the excitation period (none without one)";
    keys.push_back(hmax);
  }
  keys.push_back(count("contact", "max_events",
                       "the most switching events a run may have before it fails", 1e6, 1,
                       kMaxSteps));
  keys.push_back(choice("contact", "lcp_solver",
                        "the Siconos LCP solver for several contacts switching at once",
                        {"lemke", "enumerative"}, "lemke"));
  return keys;
}

}  // namespace

const std::vector<KeySpec>& common_keys() {
  static const std::vector<KeySpec> keys = table();
  return keys;
}

const KeySpec& common_key(const std::string& dotted) {
  for (const auto& k : common_keys())
    if (k.dotted() == dotted) return k;
  throw std::logic_error("no common case key '" + dotted + "'");
}

}  // namespace pcsim::sim
