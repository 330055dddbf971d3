// Shared by the switching tests: load a contact model of models/contact/, run it with
// switching, and sample its state on the way.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/contacts/switching.hpp"
#include "modelfile/model_file.hpp"

namespace switching_test {

using namespace pcsim;
using namespace pcsim::mech;

inline std::shared_ptr<const Model> contact_model(const std::string& stem,
                                                  const std::map<std::string, double>& p,
                                                  const Eigen::VectorXd& q0 = Eigen::VectorXd()) {
  const auto d = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/models/contact/" + stem + ".toml");
  return d->instantiate(p, q0, 0.0);
}

inline std::vector<std::string> all_constraints(const Model& m) {
  std::vector<std::string> names;
  for (const auto& c : m.constraints()) names.push_back(c.name);
  return names;
}

struct Trace {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> q, qd, R, derived;  ///< derived: the model's outputs
  std::vector<std::vector<ContactMode>> modes;
};

/// Runs with switching; every accepted step end is recorded in `trace` (if given).
inline SwitchingResult run(const Model& m, const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0,
                           double t_end, SimulationOptions o = {}, SwitchingOptions sw = {},
                           Trace* trace = nullptr) {
  o.t_end = t_end;
  if (o.active_constraints.empty()) o.active_constraints = all_constraints(m);
  return simulate_switching(m, q0, qd0, o, sw, [trace](const StepView& v, const std::vector<ContactMode>& modes) {
    if (trace) {
      const Sample& s = v.sample(v.t);
      trace->t.push_back(v.t);
      trace->q.push_back(s.q);
      trace->qd.push_back(s.qd);
      trace->R.push_back(s.R);
      trace->derived.push_back(s.derived);
      trace->modes.push_back(modes);
    }
    return true;
  });
}

inline std::vector<ContactEvent> events_of(const SwitchingResult& r, ContactEventKind kind) {
  std::vector<ContactEvent> out;
  for (const auto& e : r.events)
    if (e.kind == kind) out.push_back(e);
  return out;
}

}  // namespace switching_test
