// The switching run's summary object, events.csv and report lines (switching_summary.hpp).
#include "sim/switching_summary.hpp"

#include <cmath>
#include <sstream>

#include "common/format.hpp"

namespace pcsim::sim {

namespace {

nlohmann::json totals(const mech::ContactStats::Totals& t, double length) {
  auto frac = [length](double x) {
    return length > 0 ? nlohmann::json(x / length) : nlohmann::json(nullptr);
  };
  return {{"contact_fraction", frac(t.closed_time)},
          {"slip_fraction", frac(t.slip_time)},
          {"flights", t.flights},
          {"lift_offs", t.lift_offs},
          {"impacts", t.impacts},
          {"slips", t.slips},
          {"sticks", t.sticks},
          {"reversals", t.reversals},
          {"max_flight_height", t.max_flight_height},
          {"max_impact_velocity", t.max_impact_velocity},
          {"slip_distance", t.slip_distance},
          {"energy_impacts", t.energy_impacts},
          {"energy_friction", t.energy_friction},
          {"flight_fraction", frac(t.flight_time)},
          {"penetration_max", t.penetration_max},
          {"penetration_time", std::isfinite(t.penetration_time) ? nlohmann::json(t.penetration_time)
                                                                 : nlohmann::json(nullptr)}};
}

}  // namespace

nlohmann::json switching_summary(const mech::SwitchingResult& r, const Setup& s) {
  nlohmann::json j;
  nlohmann::json contacts = nlohmann::json::object();
  double ei = 0, ef = 0, wi = 0, wf = 0, pen = 0;
  const double run_length = r.t - 0.0;
  for (const auto& c : r.contacts) {
    nlohmann::json o;
    o["friction"] = c.friction.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.friction);
    const std::size_t k = static_cast<std::size_t>(&c - r.contacts.data());
    o["initial_mode"] = k < r.initial_modes.size() ? mech::to_string(r.initial_modes[k]) : "unknown";
    o["run"] = totals(c.run, run_length);
    o["window"] = totals(c.window, r.window_length);
    o["gap_end"] = c.gap_end;
    o["gap_tolerance_end"] = c.gap_tol_end;
    o["inside_at_end"] = c.gap_end < -c.gap_tol_end;
    contacts[c.name] = o;
    pen = std::max(pen, c.run.penetration_max);
    ei += c.run.energy_impacts;
    ef += c.run.energy_friction;
    wi += c.window.energy_impacts;
    wf += c.window.energy_friction;
  }
  j["contacts"] = contacts;
  j["energy_dissipated"] = {{"impacts", ei}, {"friction", ef}, {"window_impacts", wi}, {"window_friction", wf}};
  j["events"] = r.events.size();
  j["segments"] = r.segments;
  j["lcp_solves"] = r.lcp_solves;
  j["late_roots"] = r.late_roots;
  j["penetration_max"] = pen;
  j["energy_limited_impacts"] = r.energy_limited_impacts;
  j["energy_prevented_max"] = r.energy_prevented_max;
  j["zeno_time"] = s.contact.zeno_time;
  j["flight_hmax"] = s.contact.flight_hmax;
  if (std::isfinite(s.period)) j["window_periods"] = r.window_length / s.period;
  return j;
}

std::string events_csv(const mech::SwitchingResult& r) {
  std::string out =
      "t,kind,constraint,mode_before,mode_after,normal,tangential,vn_before,vn_after,vt_before,"
      "vt_after,energy_lost\n";
  for (const auto& e : r.events) {
    if (std::isfinite(e.t)) append_number(out, e.t);
    out += ',';
    out += mech::to_string(e.kind);
    out += ',' + e.constraint + ',' + mech::to_string(e.mode_before) + ',' + mech::to_string(e.mode_after);
    for (double v : {e.normal, e.tangential, e.vn_before, e.vn_after, e.vt_before, e.vt_after, e.energy_lost}) {
      out += ',';
      if (std::isfinite(v)) append_number(out, v);  // else empty: no "nan" token in a CSV
    }
    out += '\n';
  }
  return out;
}

std::string switching_report(const nlohmann::json& sw) {
  if (sw.is_null()) return "";
  std::ostringstream os;
  const bool periodic = sw.contains("window_periods") && sw["window_periods"].get<double>() > 0;
  const double periods = periodic ? sw["window_periods"].get<double>() : 0.0;
  os << "  switching contacts: " << sw["events"].get<long>() << " events over the run ("
     << sw["segments"].get<long>() << " integrations";
  if (sw["lcp_solves"].get<long>() > 0) os << ", " << sw["lcp_solves"].get<long>() << " LCPs solved by Siconos";
  os << ")\n";
  if (sw.value("energy_limited_impacts", 0L) > 0)
    os << "    " << sw["energy_limited_impacts"].get<long>()
       << " impacts where Newton's restitution would have created kinetic energy (up to "
       << format_significant(sw["energy_prevented_max"].get<double>(), 3)
       << " J): restitution reduced until it does not (docs/switching.md, the energy rule)\n";
  for (const auto& [name, c] : sw["contacts"].items()) {
    const auto& w = c["window"];
    const double cf = w["contact_fraction"].is_null() ? NAN : w["contact_fraction"].get<double>();
    const long lifts = w["flights"].get<long>(), impacts = w["impacts"].get<long>();
    os << "    '" << name << "' over the window: ";
    if (lifts == 0 && impacts == 0 && cf >= 1.0 - 1e-12) {
      os << "never leaves the surface";
    } else if (lifts == 0 && impacts == 0 && cf <= 1e-12) {
      os << "never touches";
    } else {
      os << "leaves " << lifts << (lifts == 1 ? " time" : " times");
      if (periodic) {
        const double per = lifts / periods;
        os << " (" << (std::abs(per - std::round(per)) < 0.05 && per >= 0.95
                           ? (std::round(per) == 1 ? std::string("once") : format_significant(std::round(per), 3) + " times") +
                                 " per period"
                           : format_significant(per, 3) + " per period")
           << ")";
      }
      // The time in flight from the flights recorded (flight_fraction); summaries written
      // before it existed: 1 - contact_fraction.
      const double ff = w.contains("flight_fraction") && w["flight_fraction"].is_number()
                            ? w["flight_fraction"].get<double>()
                            : 1.0 - cf;
      os << ", in flight " << format_significant(100.0 * ff, 3) << " % of the time, up to "
         << format_significant(w["max_flight_height"].get<double>(), 3) << " m; " << impacts
         << (impacts == 1 ? " impact" : " impacts") << ", landing at up to "
         << format_significant(w["max_impact_velocity"].get<double>(), 3) << " m/s";
    }
    if (!c["friction"].is_null()) {
      const double d = w["slip_distance"].get<double>();
      if (w["slips"].get<long>() == 0 && d == 0.0 && w["slip_fraction"].is_number() &&
          w["slip_fraction"].get<double>() == 0.0)
        os << "; no slip";
      else
        os << "; slips " << format_significant(d, 3) << " m (" << w["slips"].get<long>()
           << " onsets, " << format_significant(100.0 * w["slip_fraction"].get<double>(), 3)
           << " % of the time)";
    }
    if (c["run"].contains("penetration_max")) {
      const double pm = c["run"]["penetration_max"].get<double>();
      if (pm > 0.0)
        os << "\n      deepest penetration " << format_significant(pm, 3) << " m (t = "
           << format_significant(c["run"]["penetration_time"].get<double>(), 9) << " s)";
      else
        os << "\n      never below its surface";
      if (c.value("inside_at_end", false))
        os << "; WARNING: ends " << format_significant(-c["gap_end"].get<double>(), 3)
           << " m inside (beyond the gap's accuracy " << format_significant(c["gap_tolerance_end"].get<double>(), 3)
           << " m)";
    }
    os << "\n      energy lost in the window: " << format_significant(w["energy_impacts"].get<double>(), 3)
       << " J in impacts, " << format_significant(w["energy_friction"].get<double>(), 3)
       << " J by sliding friction; over the run: " << c["run"]["lift_offs"].get<long>() << " lift-offs, "
       << c["run"]["impacts"].get<long>() << " impacts, " << c["run"]["flights"].get<long>() << " flights\n";
  }
  return os.str();
}

}  // namespace pcsim::sim
