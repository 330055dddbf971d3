// The status of an ODE/DAE integration (pcsim::OdeStatus), shared by every integrator kernel:
// the enum, its name and its one-line meaning all come from the one table in
// bridge/pcsim_ode_status.h, whose codes are the kernels' IDID values.
#pragma once

#include "pcsim_ode_status.h"

namespace pcsim {

/// What an integration ended with. The value of each enumerator is the kernels' IDID code
/// (bad_input stands for every IDID < 0). See docs/radau.md, "Statuses".
enum class OdeStatus : int {
#define PCSIM_ODE_STATUS_CXX(name, code, meaning) name = code,
  PCSIM_ODE_STATUS_TABLE(PCSIM_ODE_STATUS_CXX)
#undef PCSIM_ODE_STATUS_CXX
};

/// The enumerator's name, e.g. "newton_failure" ("unknown" for a value outside the table).
const char* to_string(OdeStatus status);

/// The one-line meaning of a status, as in the table.
const char* meaning(OdeStatus status);

/// The status of a kernel's IDID: every IDID < 0 is bad_input; a code outside the table is
/// callback_error (it can only come from a corrupted run).
OdeStatus ode_status_from_idid(int idid);

/// True for success, stopped_by_callback and root_found (the run ended where it was asked to).
inline bool is_ordinary_return(OdeStatus s) {
  return s == OdeStatus::success || s == OdeStatus::stopped_by_callback ||
         s == OdeStatus::root_found;
}

}  // namespace pcsim
