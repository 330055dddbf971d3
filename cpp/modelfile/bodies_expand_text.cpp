// `pcsim expand`: a ModelSource printed as an energy-form model file (bodies.hpp).
#include <cmath>
#include <sstream>

#include "common/format.hpp"
#include "modelfile/bodies.hpp"

namespace pcsim::modelfile::bodies {

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') { out += "\\n"; continue; }
    if (c == '\t') { out += "\\t"; continue; }
    if (c == '\r') { out += "\\r"; continue; }
    out += c;
  }
  return out + "\"";
}

std::string num(double v) {
  std::string s = format_number(v);
  return s;
}

std::string point_ref(const DrawSpec& d, int i) {
  const DrawPoint& p = d.points[static_cast<std::size_t>(i)];
  if (p.named) return quoted(p.name);
  std::string s = "{ x = " + quoted(p.x) + ", y = " + quoted(p.y);
  if (!p.z.empty()) s += ", z = " + quoted(p.z);
  return s + " }";
}

}  // namespace

std::string energy_form_text(const detail::ModelSource& src) {
  std::ostringstream o;
  o << "# The energy form pcsim derived from " << (src.file.empty() ? std::string("a model") : src.file.filename().string())
    << " (pcsim expand). Running this file gives the same results.\n";
  o << "[model]\n";
  o << "name = " << quoted(src.name) << "\n";
  o << "coordinates = [";
  for (std::size_t i = 0; i < src.coordinates.size(); ++i) o << (i ? ", " : "") << quoted(src.coordinates[i]);
  o << "]\n";
  if (src.period) o << "period = " << quoted(src.period->text) << "\n";
  // The expanded file must derive as the body model does (an energy-form file keeps h as
  // written unless told).
  o << "velocity_terms = " << quoted(src.expand_velocity_terms ? "expanded" : "as_written") << "\n";
  if (!src.slow.empty()) {
    o << "slow = [";
    for (std::size_t i = 0; i < src.slow.size(); ++i) o << (i ? ", " : "") << quoted(src.slow[i]);
    o << "]\n";
  }
  if (!src.parameters.empty()) {
    o << "\n[model.parameters]\n";
    for (const ParameterSpec& p : src.parameters) {
      o << p.name << " = { value = " << num(p.value);
      if (!p.unit.empty()) o << ", unit = " << quoted(p.unit);
      if (!p.meaning.empty()) o << ", meaning = " << quoted(p.meaning);
      if (std::isfinite(p.min)) o << ", min = " << num(p.min);
      if (std::isfinite(p.max)) o << ", max = " << num(p.max);
      if (p.min_exclusive) o << ", min_exclusive = true";
      if (p.max_exclusive) o << ", max_exclusive = true";
      o << " }\n";
    }
  }
  if (!src.definitions.empty()) {
    o << "\n[model.define]\n";
    for (const auto& [name, e] : src.definitions) o << name << " = " << quoted(e.text) << "\n";
  }
  o << "\n[model.energy]\n";
  o << "kinetic = " << quoted(src.kinetic.text) << "\n";
  if (!src.potential.text.empty()) o << "potential = " << quoted(src.potential.text) << "\n";
  if (!src.dissipation.text.empty()) o << "dissipation = " << quoted(src.dissipation.text) << "\n";
  if (!src.forces.empty()) {
    o << "\n[model.forces]\n";
    for (const auto& [i, e] : src.forces) o << src.coordinates[static_cast<std::size_t>(i)] << " = " << quoted(e.text) << "\n";
  }
  for (const auto& c : src.constraints) {
    if (c.spec.added) continue;
    o << "\n[[model.constraint]]\n";
    o << "name = " << quoted(c.spec.name) << "\n";
    if (c.spec.kind == mech::ConstraintKind::holonomic) {
      o << "holonomic = " << quoted(c.spec.holonomic) << "\n";
    } else {
      o << "velocity = { ";
      for (std::size_t k = 0; k < c.spec.velocity.size(); ++k)
        o << (k ? ", " : "") << c.spec.velocity[k].first << " = " << quoted(c.spec.velocity[k].second);
      o << " }\n";
      if (!c.spec.velocity0.empty()) o << "velocity0 = " << quoted(c.spec.velocity0) << "\n";
    }
    if (!c.spec.active_by_default) o << "active = false\n";
    if (c.spec.from_initial) o << "from_initial = true\n";
    if (c.spec.unilateral) o << "unilateral = true\n";
    if (c.spec.gap_sign != 1) o << "gap_sign = " << c.spec.gap_sign << "\n";
    if (!c.spec.restitution.empty()) o << "restitution = " << quoted(c.spec.restitution) << "\n";
    if (!c.spec.friction.empty()) o << "friction = " << quoted(c.spec.friction) << "\n";
    if (c.spec.rough) o << "rough = true\n";
    if (!c.spec.mu_static.empty()) o << "mu_static = " << quoted(c.spec.mu_static) << "\n";
    if (!c.spec.mu_kinetic.empty()) o << "mu_kinetic = " << quoted(c.spec.mu_kinetic) << "\n";
  }
  if (!src.outputs.empty()) {
    o << "\n[model.outputs]\n";
    for (const auto& [name, e] : src.outputs) o << name << " = " << quoted(e.text) << "\n";
  }
  const DrawSpec& d = src.draw;
  if (!d.empty()) {
    o << "\n[model.draw]\n";
    o << "view = " << (d.spatial ? "\"3d\"" : "\"2d\"") << "\n";
    if (d.magnify != 1.0) o << "magnify = " << num(d.magnify) << "\n";
    for (const DrawPoint& p : d.points) {
      if (!p.named) continue;
      o << "[[model.draw.point]]\nname = " << quoted(p.name) << "\nx = " << quoted(p.x) << "\ny = " << quoted(p.y) << "\n";
      if (!p.z.empty()) o << "z = " << quoted(p.z) << "\n";
      if (p.follows >= 0) o << "follows = " << quoted(d.points[static_cast<std::size_t>(p.follows)].name) << "\n";
    }
    for (const DrawShape& s : d.shapes) {
      switch (s.kind) {
        case DrawShape::Kind::line:
        case DrawShape::Kind::polygon: {
          o << (s.kind == DrawShape::Kind::line ? "[[model.draw.line]]\n" : "[[model.draw.polygon]]\n");
          o << "points = [";
          for (std::size_t k = 0; k < s.points.size(); ++k) o << (k ? ", " : "") << point_ref(d, s.points[k]);
          o << "]\n";
          if (s.kind == DrawShape::Kind::line && s.closed) o << "closed = true\n";
          if (!s.fill.empty()) o << "fill = " << quoted(s.fill) << "\n";
          break;
        }
        case DrawShape::Kind::circle:
          o << "[[model.draw.circle]]\ncentre = " << point_ref(d, s.points[0]) << "\nradius = " << quoted(s.radius) << "\n";
          if (!s.fill.empty()) o << "fill = " << quoted(s.fill) << "\n";
          break;
        case DrawShape::Kind::arrow:
          o << "[[model.draw.arrow]]\nat = " << point_ref(d, s.points[0]) << "\nforce = " << quoted(s.force) << "\n";
          o << "direction = { x = " << quoted(s.dx) << ", y = " << quoted(s.dy);
          if (!s.dz.empty()) o << ", z = " << quoted(s.dz);
          o << " }\nunit = " << num(s.unit) << "\nlength = " << num(s.length) << "\n";
          if (!s.unit_name.empty()) o << "unit_name = " << quoted(s.unit_name) << "\n";
          break;
      }
      if (!s.color.empty()) o << "color = " << quoted(s.color) << "\n";
      if (!s.mode.empty()) o << "mode = " << quoted(s.mode) << "\n";
    }
  }
  return o.str();
}

}  // namespace pcsim::modelfile::bodies
