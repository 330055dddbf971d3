// The contact attributes of issue 12 on the rows of the joints that can lift off or slip
// (bodies.hpp, docs/bodies.md "Contact"): `unilateral` and `restitution` go on the joint's gap
// row (a distance, so its multiplier is the normal force in N), `mu_static` and `mu_kinetic` on
// its sliding row (the contact point's sliding velocity in m/s, so its multiplier is the friction
// force in N), or on its two sliding rows where the contact slides in a plane (a 2-D Coulomb
// cone: the sliding velocity's components along two orthonormal tangents). They become the
// [[model.constraint]] attributes of docs/model-files.md ("Contact") on the generated rows, and
// `pcsim expand` prints them there. The rolling joints' surfaces (a line or a circle, a plane
// or a sphere) are read here too: the contact's geometry, one vocabulary for all of them.
#include <cmath>
#include <string>
#include <vector>

#include "common/format.hpp"
#include "modelfile/bodies.hpp"

namespace pcsim::modelfile::bodies {

const std::vector<std::string>& contact_keys() {
  static const std::vector<std::string> k{"unilateral", "restitution", "mu_static", "mu_kinetic"};
  return k;
}

bool has_contact_keys(const Joint& j) {
  if (!j.table) return false;
  for (const auto& k : contact_keys())
    if (j.table->get(k)) return true;
  return false;
}

void refuse_contact_keys(Expander& x, const Joint& j, const std::string& why) {
  if (!j.table) return;
  for (const auto& k : contact_keys())
    if (j.table->get(k)) x.fail(j.key + "." + k, why);
}

namespace {
// "got TEXT = VALUE" (the value only when the text is not that number already).
std::string got(const Expr& e, double v) {
  const std::string n = format_number(v);
  return "got " + e + (e == n ? "" : " = " + n);
}
}  // namespace

void read_joint_contact(Expander& x, const Joint& j, Row& normal, Row* friction,
                        const std::string& no_friction, Row* friction2) {
  const toml::table& t = *j.table;
  auto value = [&](const Expr& e, const std::string& k) {
    return default_parameter_value(x, e, j.key + "." + k);
  };
  if (auto u = t.get("unilateral")) normal.unilateral = x.boolean(*u, j.key + ".unilateral");
  const Expr e = x.optional(t, j.key, "restitution");
  if (!e.empty()) {
    if (!normal.unilateral)
      x.fail(j.key + ".restitution",
             "restitution only with unilateral = true (Newton's coefficient of a contact that can open)");
    const double v = value(e, "restitution");
    if (!std::isnan(v) && !(v >= 0.0 && v <= 1.0))
      x.fail(j.key + ".restitution",
             "Newton's restitution coefficient in [0, 1], " + got(e, v));
    normal.restitution = e;
  }
  const Expr ms = x.optional(t, j.key, "mu_static");
  const Expr mk = x.optional(t, j.key, "mu_kinetic");
  if (ms.empty() && !mk.empty())
    x.fail(j.key + ".mu_kinetic",
           "mu_kinetic only with mu_static (Coulomb's static coefficient; mu_kinetic defaults to it)");
  if (ms.empty()) return;
  if (!friction) x.fail(j.key + ".mu_static", no_friction);
  if (!normal.unilateral)
    x.fail(j.key + ".mu_static",
           "friction (mu_static) only with unilateral = true (Coulomb's law bounds the friction "
           "force by the normal force of a contact that can open)");
  const double s = value(ms, "mu_static");
  if (!std::isnan(s) && !(s >= 0.0 && std::isfinite(s)))
    x.fail(j.key + ".mu_static", "a static friction coefficient >= 0, " + got(ms, s));
  if (!mk.empty()) {
    const double k = value(mk, "mu_kinetic");
    if (!std::isnan(k) && !std::isnan(s) && !(k >= 0.0 && k <= s))
      x.fail(j.key + ".mu_kinetic", "a kinetic friction coefficient in [0, mu_static = " +
                                        format_number(s) + "], " + got(mk, k));
  }
  // The same coefficients on each friction row of the contact (one row, or the cone's two).
  for (Row* f : {friction, friction2}) {
    if (!f) continue;
    f->mu_static = ms;
    f->mu_kinetic = mk;
    f->friction = normal.name;
  }
}

RollingSurface read_rolling_surface(Expander& x, const Joint& j, const std::string& body,
                                    const Expr& body_radius, const std::string& flat,
                                    const std::string& flat_where, const std::string& curved) {
  const toml::table& t = *j.table;
  const std::string radius_key = curved + "_radius";
  const double r = default_parameter_value(x, body_radius, j.key + ".radius");
  if (!std::isnan(r) && !(r > 0.0))
    x.fail(j.key + ".radius", "the " + body + "'s radius > 0, " + got(body_radius, r));
  std::string surface = flat;
  if (const toml::node* sf = t.get("surface"))
    surface = x.string(*sf, j.key + ".surface", "\"" + flat + "\" or \"" + curved + "\"");
  RollingSurface s;
  s.curved = surface == curved;
  if (!s.curved) {
    if (surface != flat)
      x.fail(j.key + ".surface", "\"" + flat + "\" (default: " + flat_where + ") or \"" + curved +
                                     "\" (centred at marker1, radius " + radius_key + "), got '" + surface + "'");
    for (const std::string& key : {radius_key, std::string("inside")})
      if (t.get(key))
        x.fail(j.key + "." + key, "no " + key + " on a " + body + " on a " + flat + " (surface = \"" + curved + "\" takes it)");
    return s;
  }
  s.radius = x.required(t, j.key, radius_key, "the " + curved + "'s radius (an expression; the " + curved + " is centred at marker1)");
  if (const toml::node* in = t.get("inside")) s.inside = x.boolean(*in, j.key + ".inside");
  const double rs = default_parameter_value(x, s.radius, j.key + "." + radius_key);
  if (!std::isnan(rs) && !(rs > 0.0))
    x.fail(j.key + "." + radius_key, "the " + curved + "'s radius > 0, " + got(s.radius, rs));
  if (s.inside && !std::isnan(rs) && !std::isnan(r) && !(rs > r))
    x.fail(j.key + "." + radius_key, "a radius > the " + body + "'s radius = " + format_number(r) + " with inside = true (the " +
                                         body + " rolls inside the " + curved + "), " + got(s.radius, rs));
  return s;
}

}  // namespace pcsim::modelfile::bodies
