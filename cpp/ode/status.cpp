// Names and meanings of OdeStatus, expanded from the table in bridge/pcsim_ode_status.h.
#include "ode/status.hpp"

namespace pcsim {

const char* to_string(OdeStatus status) {
  switch (status) {
#define PCSIM_ODE_STATUS_NAME(name, code, meaning) \
  case OdeStatus::name: return #name;
    PCSIM_ODE_STATUS_TABLE(PCSIM_ODE_STATUS_NAME)
#undef PCSIM_ODE_STATUS_NAME
  }
  return "unknown";
}

const char* meaning(OdeStatus status) {
  switch (status) {
#define PCSIM_ODE_STATUS_MEANING(name, code, text) \
  case OdeStatus::name: return text;
    PCSIM_ODE_STATUS_TABLE(PCSIM_ODE_STATUS_MEANING)
#undef PCSIM_ODE_STATUS_MEANING
  }
  return "unknown status";
}

OdeStatus ode_status_from_idid(int idid) {
  if (idid < 0) return OdeStatus::bad_input;
  switch (idid) {
#define PCSIM_ODE_STATUS_CODE(name, code, text) \
  case code: return OdeStatus::name;
    PCSIM_ODE_STATUS_TABLE(PCSIM_ODE_STATUS_CODE)
#undef PCSIM_ODE_STATUS_CODE
  }
  return OdeStatus::callback_error;
}

}  // namespace pcsim
