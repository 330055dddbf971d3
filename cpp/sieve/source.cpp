// The sieve's model source and client for the generic case and run layers.
#include "sieve/source.hpp"

#include <cmath>
#include <mutex>
#include <stdexcept>

#include "common/error.hpp"
#include "sieve/run.hpp"
#include "sim/client.hpp"
#include "sim/builtin_models.hpp"
#include "sim/file_source.hpp"

namespace pcsim::sieve {

namespace {

constexpr double kPi = 3.14159265358979323846;

class SieveSource final : public sim::ModelSource {
 public:
  SieveSource() {
    // The parameters, their defaults, units, meanings and limits are the model file's
    // (models/sieve_1995.toml), in the order of the case format (a case's keys are written in
    // it, e.g. by to_toml). One is the sieve's own key: t_runup selects the exciter's run-up
    // model (models/sieve_1995_runup.toml, where it is a parameter > 0); 0, its default, is the
    // paper's exciter at full speed from t = 0.
    const auto file = sim::embedded_description("sieve_1995");
    auto spec = [&file](const std::string& name) {
      for (const auto& p : file->parameters())
        if (p.name == name) return sim::parameter_spec(p);
      throw std::logic_error("models/sieve_1995.toml: no parameter " + name);
    };
    for (const char* name : {"m0", "m1", "m2", "J0", "J1", "J2", "r", "e", "cx", "cy", "ctheta",
                             "bx", "by", "btheta", "omega", "g", "x0", "y0", "xc", "yc", "xb",
                             "yb", "a", "b", "u0", "f"})
      parameters_.push_back(spec(name));
    sim::ParameterSpec t_runup;
    t_runup.name = "t_runup";
    t_runup.unit = "s";
    t_runup.meaning =
        "exciter run-up time: its speed ramps from 0 to omega over it (models/"
        "sieve_1995_runup.toml); 0: at full speed from t = 0, as in the paper";
    t_runup.min = 0.0;
    parameters_.push_back(t_runup);
    parameters_.push_back(spec("e_n"));
    coordinates_ = file->coordinates();
    constraints_ = {{"contact", mech::ConstraintKind::holonomic, true, "(3.1) u = u0", true, ""},
                    {"rolling", mech::ConstraintKind::holonomic, true,
                     "(3.2) rolling without slip, s + r phi = const (erratum 7)", false, "contact"},
                    {"lock_theta", mech::ConstraintKind::holonomic, false, "theta = 0", false, ""}};
    outputs_ = {"fstar"};
  }
  const std::string& name() const override { return name_; }
  std::string origin() const override { return "built-in model 'sieve'"; }
  const std::vector<std::string>& coordinates() const override { return coordinates_; }
  const std::vector<sim::ParameterSpec>& parameters() const override { return parameters_; }
  const std::vector<sim::ConstraintOffer>& constraints() const override { return constraints_; }
  const std::vector<std::string>& outputs() const override { return outputs_; }
  double period(const sim::ParameterValues& p) const override {
    const auto it = p.find("omega");
    return (it != p.end() && it->second > 0) ? 2 * kPi / it->second
                                             : std::numeric_limits<double>::quiet_NaN();
  }
  // The roller drifts slowly along the statically tilted deck (models/sieve_1995.toml).
  std::vector<std::string> slow_coordinates() const override {
    return sim::embedded_description("sieve_1995")->slow_coordinates();
  }
  // The drawing of a run (model.toml, for pcsim animate): the paper's model file; its run-up
  // variant has the same coordinates and drawing.
  std::string definition_text() const override { return sim::embedded_model_text("sieve_1995"); }
  // The paper's model as a model file (models/sieve_1995.toml, embedded), T (3.4) and Q
  // (3.4a)-(3.4f) with the errata, derived symbolically and evaluated from a flat tape; with
  // t_runup > 0 its exciter run-up (models/sieve_1995_runup.toml). (The C++ forms of the same
  // machine, which tests prove equal, are the tests' variants: tests/sieve/support.)
  std::shared_ptr<const mech::Model> instantiate(const sim::ParameterValues& parameters,
                                                 const Eigen::VectorXd& q0, double t0,
                                                 const toml::table& case_table,
                                                 const std::string& variant) const override {
    if (!variant.empty() && variant != "model_file")
      throw InputError("the sieve has no model variant '" + variant + "'");
    sim::ParameterValues p = parameters;
    const auto tr = p.find("t_runup");
    const double t_runup = tr == p.end() ? 0.0 : tr->second;
    if (tr != p.end()) p.erase(tr);
    if (t_runup > 0) {
      p["t_runup"] = t_runup;
      return sim::embedded_description("sieve_1995_runup")->instantiate(p, q0, t0);
    }
    return sim::embedded_description("sieve_1995")->instantiate(p, q0, t0);
  }

 private:
  std::string name_ = "sieve";
  std::vector<std::string> coordinates_, outputs_;
  std::vector<sim::ParameterSpec> parameters_;
  std::vector<sim::ConstraintOffer> constraints_;
};

}  // namespace

void register_sieve() {
  static std::once_flag once;
  std::call_once(once, [] {
    sim::register_builtin("sieve", [] { return std::make_shared<const SieveSource>(); });
    sim::register_client("sieve", make_sieve_client());
    sim::set_default_builtin("sieve");  // a case without `model` is a sieve case
  });
}

}  // namespace pcsim::sieve
