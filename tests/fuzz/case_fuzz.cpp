#include "case_fuzz.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/error.hpp"
#include "common/files.hpp"
#ifdef PCSIM_WITH_SIEVE
#include "sieve/source.hpp"
#endif
#include "sim/case.hpp"
#include "sim/run.hpp"

namespace pcsim::testing {

FuzzOutcome fuzz_case_input(const std::string& text, std::string* what) {
#ifdef PCSIM_WITH_SIEVE
  // With the sieve built, its cases (model = "sieve", or no model) are seeds too.
  static const bool registered = (pcsim::sieve::register_sieve(), true);
  (void)registered;
#endif
  // Model files named by a case are looked up beside this (virtual) case file: the shipped
  // cases' directory, so the seeds' relative model paths resolve.
  static const std::filesystem::path anchor =
      std::filesystem::path(PCSIM_SOURCE_DIR) / "cases" / "fuzz_input.toml";
  try {
    sim::Case c = sim::load_case_text(text, anchor);
    // A short run: at most 2 ms of motion and 20 output rows' worth of work.
    if (c.setup.t_end > 2e-3) sim::set_value(c, {"solver.t_end", "0.002"});
    // A sane case needs < 100 steps for 2 ms; an absurd one (a spring attached 1e18 m away)
    // would need billions: it fails with "too many steps" after 2000.
    if (c.setup.max_steps > 2000)
      sim::set_value(c, {"solver.max_steps", "2000"});
    sim::run_case(c);
    return FuzzOutcome::loaded_and_ran;
  } catch (const InputError&) {
    return FuzzOutcome::refused;
  } catch (const NumericalError&) {
    return FuzzOutcome::numerical_failure;
  } catch (const IoError&) {
    return FuzzOutcome::refused;
  } catch (const std::exception& e) {
    if (what) *what = std::string(typeid(e).name()) + ": " + e.what();
    return FuzzOutcome::defect;
  } catch (...) {
    if (what) *what = "a non-standard exception";
    return FuzzOutcome::defect;
  }
}

}  // namespace pcsim::testing
