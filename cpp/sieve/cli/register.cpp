// The sieve in the pcsim executable (compiled into it when the sieve is built, pcsim_application in cmake/pcsim_helpers.cmake):
// the built-in model "sieve", its client and the default model of a case without `model` are
// registered before any command runs.
#include "cli/commands.hpp"
#include "sieve/source.hpp"

namespace {

void setup(CLI::App&) { pcsim::sieve::register_sieve(); }

[[maybe_unused]] const bool registered = pcsim::cli::register_command(0, &setup);

}  // namespace
