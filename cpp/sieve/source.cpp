// The sieve's model source and client for the generic case and run layers.
#include "sieve/source.hpp"

#include <cmath>
#include <mutex>

#include "common/error.hpp"
#include "sieve/model.hpp"
#include "sieve/run.hpp"
#include "sieve/settings.hpp"
#include "sim/client.hpp"
#include "sim/file_source.hpp"

namespace pcsim::sieve {

namespace {

constexpr double kPi = 3.14159265358979323846;

sim::ParameterSpec par(const char* name, double value, const char* unit, const char* meaning,
                       double min = -INFINITY, bool min_exclusive = false) {
  sim::ParameterSpec p;
  p.name = name;
  p.value = value;
  p.unit = unit;
  p.meaning = meaning;
  p.min = min;
  p.min_exclusive = min_exclusive;
  return p;
}

class SieveSource final : public sim::ModelSource {
 public:
  SieveSource() {
    const SieveParameters d;
    const double pos = 0.0;
    parameters_ = {
        // Printed in the paper.
        par("m0", d.m0, "kg", "unbalanced mass", pos),
        par("m1", d.m1, "kg", "desk mass", pos, true),
        par("m2", d.m2, "kg", "roller mass", pos, true),
        par("J0", d.J0, "kg m^2", "exciter inertia", pos),
        par("J1", d.J1, "kg m^2", "desk inertia", pos, true),
        par("J2", d.J2, "kg m^2", "roller inertia", pos, true),
        par("r", d.r, "m", "roller radius", pos, true),
        par("e", d.e, "m", "eccentricity", pos),
        par("cx", d.cx, "N/m",
            "vertical stiffness; > 0: it carries the static preload (m0 + m1 + m2) g / cx", pos,
            true),
        par("cy", d.cy, "N/m", "horizontal stiffness", pos),
        par("ctheta", d.ctheta, "N m/rad", "torsional stiffness", pos),
        par("bx", d.bx, "N s/m", "vertical damping", pos),
        par("by", d.by, "N s/m", "horizontal damping", pos),
        par("btheta", d.btheta, "N m s/rad", "torsional damping", pos),
        par("omega", d.omega, "rad/s",
            "excitation frequency; > 0: the sieve is driven by its exciter, and its summary "
            "window is a number of excitation periods",
            pos, true),
        // Not printed: the project's documented defaults (assumptions).
        par("g", d.g, "m/s^2",
            "gravity; > 0: the contact margin min R_u/(m2 g) is relative to the roller's weight",
            pos, true),
        par("x0", d.x0, "m", "exciter axis eta"),
        par("y0", d.y0, "m", "exciter axis xi"),
        par("xc", d.xc, "m", "horizontal spring eta"),
        par("yc", d.yc, "m", "vertical spring xi"),
        par("xb", d.xb, "m", "horizontal damper eta"),
        par("yb", d.yb, "m", "vertical damper xi"),
        par("a", d.a, "m", "horizontal spring/damper xi"),
        par("b", d.b, "m", "vertical spring/damper eta"),
        par("u0", d.u0, "m", "roller centre height over C"),
        par("f", d.f, "", "friction coefficient roller/deck", pos, true),
        // Issue 12: the restitution of a landing when contacts switch (contact.switching).
        // Not in the paper: the exciter's run-up for transient studies (docs/steady.md).
        par("t_runup", 0.0, "s",
            "exciter run-up time: its speed ramps from 0 to omega over it (models/"
            "sieve_1995_runup.toml); 0: at full speed from t = 0, as in the paper",
            pos),
        // Issue 12: the restitution of a landing when contacts switch (contact.switching).
        par("e_n", 0.0, "", "Newton's restitution roller/deck (with contact.switching)", pos),
    };
    parameters_.back().max = 1.0;  // e_n <= 1
    for (const char* c : kCoordinateNames) coordinates_.push_back(c);
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
  // The default: the paper's model as a model file (models/sieve_1995.toml, embedded), T (3.4)
  // and Q (3.4a)-(3.4f) with the errata, derived symbolically and evaluated from a flat tape.
  // The variants are the C++ forms of the same machine (sieve/model.hpp): "closed_form" (the
  // path before issue 14: (3.4) through the engine's automatic differentiation), "geometric"
  // and "analytic" (hand-derived); tests prove all four equal.
  std::shared_ptr<const mech::Model> instantiate(const sim::ParameterValues& parameters,
                                                 const Eigen::VectorXd& q0, double t0,
                                                 const toml::table& case_table,
                                                 const std::string& variant) const override {
    sim::ParameterValues p = parameters;
    const auto tr = p.find("t_runup");
    const double t_runup = tr == p.end() ? 0.0 : tr->second;
    if (tr != p.end()) p.erase(tr);
    if (variant.empty() || variant == "model_file") {
      if (t_runup > 0) {
        p["t_runup"] = t_runup;
        return sim::embedded_description("sieve_1995_runup")->instantiate(p, q0, t0);
      }
      return sim::embedded_description("sieve_1995")->instantiate(p, q0, t0);
    }
    if (t_runup > 0)
      throw InputError("parameters.t_runup: the sieve's model variant '" + variant +
                       "' has no exciter run-up (only the default model file has one)");
    const SieveSettings set = settings_from_table(case_table);
    ModelForm form = ModelForm::closed_form;
    if (variant == "geometric") form = ModelForm::geometric;
    else if (variant == "analytic") form = ModelForm::analytic;
    else if (variant != "closed_form")
      throw InputError("the sieve has no model variant '" + variant + "'");
    return make_sieve_model(set, form);
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
