// What a run with contact.switching adds to the output (issue 12): the summary's "switching"
// object (per contact, over the window and the run), events.csv, and the report's sentences.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "mech/contacts/switching.hpp"
#include "sim/case.hpp"

namespace pcsim::sim {

/// summary.json "switching": {contacts: {NAME: {friction, run: {...}, window: {...}}},
/// energy_dissipated: {impacts, friction, window_impacts, window_friction}, events, segments,
/// lcp_solves, late_roots, zeno_time, flight_hmax}. Per contact and span: contact_fraction,
/// slip_fraction, lift_offs, impacts, slips, sticks, reversals, max_flight_height (m),
/// max_impact_velocity (m/s), slip_distance (m), energy_impacts (J), energy_friction (J),
/// flight_fraction (from the recorded flights), penetration_max (m) and penetration_time (s);
/// per contact also gap_end, gap_tolerance_end (m) and inside_at_end; totals penetration_max,
/// energy_limited_impacts and energy_prevented_max (J) (issue 19).
nlohmann::json switching_summary(const mech::SwitchingResult& r, const Setup& s);

/// events.csv: t, kind, constraint, mode_before, mode_after, normal, tangential, vn_before,
/// vn_after, vt_before, vt_after, energy_lost (reactions N or impulses N s; m/s; J).
std::string events_csv(const mech::SwitchingResult& r);

/// The report's lines for a run's switching object (RunResult::switching; "" for null): what
/// each contact did over the window, in an engineer's words.
std::string switching_report(const nlohmann::json& switching);

}  // namespace pcsim::sim
