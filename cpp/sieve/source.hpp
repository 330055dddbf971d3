// The sieve as a built-in model of the case layer ("model = \"sieve\""): its parameters with
// their meanings and ranges (architecture.md section 4), the constraints a case switches, and
// its client (the extra keys initial.s0 and constraints.rolling_as_printed, the working-condition
// verdicts (3.1)-(3.3), the contracted summary keys, the report and the sweep columns).
#pragma once

namespace pcsim::sieve {

/// Registers the built-in model "sieve" and its client with the case layer. Idempotent and
/// thread-safe; call it before loading a case (the pcsim executable and the tests do).
void register_sieve();

}  // namespace pcsim::sieve
