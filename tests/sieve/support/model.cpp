// Building the sieve Model of a case (see model.hpp).
#include "sieve/support/model.hpp"

#include "sieve/support/analytic_model.hpp"

namespace pcsim::sieve {

const char* to_string(ModelForm form) {
  switch (form) {
    case ModelForm::geometric: return "geometric";
    case ModelForm::closed_form: return "closed_form";
    case ModelForm::analytic: return "analytic";
  }
  return "?";
}

std::shared_ptr<const mech::Model> make_sieve_model(const SieveSettings& settings,
                                                     ModelForm form) {
  SieveCommon common;
  common.p = settings.p;
  common.rolling_constant = settings.q0[3] + settings.p.r * settings.q0[5];
  common.printed_constant = settings.q0[3] - settings.p.r * settings.q0[5];
  if (form == ModelForm::analytic) return make_analytic_sieve_model(common);
  if (form == ModelForm::closed_form) {
    SieveClosedForm m;
    static_cast<SieveCommon&>(m) = common;
    return mech::make_model(m);
  }
  SieveGeometric m;
  static_cast<SieveCommon&>(m) = common;
  return mech::make_model(m);
}

std::vector<std::string> active_constraints(const SieveConstraints& c, bool rolling_velocity) {
  std::vector<std::string> names;
  if (c.contact) names.push_back("contact");
  if (c.rolling)
    names.push_back(c.rolling_as_printed ? "rolling_printed"
                                         : (rolling_velocity ? "rolling_velocity" : "rolling"));
  if (c.lock_theta) names.push_back("lock_theta");
  return names;
}

}  // namespace pcsim::sieve
