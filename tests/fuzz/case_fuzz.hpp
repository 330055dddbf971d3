// The case-file fuzz target: one input is the text of a case file. It is loaded and validated
// (every key, the model, the overrides' rules), and a case that loads is run for a moment (at
// most 2 ms of motion) so that checks which could only fail during the run are exercised too.
// Expected outcomes: the case loads (and runs), or pcsim::InputError / pcsim::NumericalError /
// pcsim::IoError with a message. Anything else (another exception, a crash, a sanitizer report)
// is a defect.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace pcsim::testing {

enum class FuzzOutcome { loaded_and_ran, refused, numerical_failure, defect };

/// Runs one input; on `defect`, *what says which exception escaped.
FuzzOutcome fuzz_case_input(const std::string& text, std::string* what);

}  // namespace pcsim::testing
