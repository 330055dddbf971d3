// Event-driven simulation of unilateral contact with Coulomb friction by switching constraints
// (issue 12): the integrator runs from event to event with a fixed set of active constraints;
// at each event (lift-off, impact, stick-slip, slip-stick) the contact modes are decided anew,
// impacts are resolved by Newton's law at impulse level, the state is projected onto the new
// set and the integration restarts. Reactions are computed by compatibility throughout; in
// slip, the friction law replaces one ideality row. See docs/switching.md.
#pragma once

#include <functional>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "lcp/lcp.hpp"
#include "mech/model.hpp"
#include "mech/simulation.hpp"

namespace pcsim::mech {

/// The state of one unilateral contact during a segment.
enum class ContactMode {
  flight,   ///< open: the constraint is removed, the gap is free (>= 0)
  contact,  ///< closed, no friction constraint attached
  stick,    ///< closed, its friction constraint imposed (no sliding)
  slip,     ///< closed, its friction constraint removed; −μ_k λ_n sign(v_t) acts along it
};
const char* to_string(ContactMode mode);
std::ostream& operator<<(std::ostream& os, ContactMode mode);
inline bool is_closed(ContactMode m) { return m != ContactMode::flight; }

enum class ContactEventKind {
  lift_off,      ///< closed -> flight: the normal force reached 0 (or an impulse elsewhere)
  impact,        ///< the gap closed with approach velocity: Newton's impulse
  accumulation,  ///< an impact whose rebound would end in accumulating impacts: closed (Zeno)
  slip,          ///< stick -> slip: |λ_t| reached μ_s λ_n
  stick,         ///< slip -> stick: the sliding velocity reached 0 and sticking is consistent
  reversal,      ///< slip -> slip the other way: the sliding velocity reached 0, sticking is not
};
const char* to_string(ContactEventKind kind);
std::ostream& operator<<(std::ostream& os, ContactEventKind kind);

/// One switching event of one contact. `normal` and `tangential` are reactions (N) for
/// lift_off, slip, stick and reversal (the values just before the switch), impulses (N s) for
/// impact and accumulation. Velocities are the contact's normal (gap rate) and sliding
/// velocities; energy_lost is this contact's share of the impact loss, −Λ·(v⁺ + v⁻)/2 (J).
struct ContactEvent {
  double t = 0.0;
  ContactEventKind kind = ContactEventKind::impact;
  int contact = 0;           ///< index into SwitchingResult::contacts
  std::string constraint;    ///< the unilateral constraint's name
  ContactMode mode_before = ContactMode::flight, mode_after = ContactMode::flight;
  double normal = 0.0, tangential = 0.0;
  double vn_before = 0.0, vn_after = 0.0, vt_before = 0.0, vt_after = 0.0;
  double energy_lost = 0.0;
  /// Newton's restitution impulse would have created kinetic energy at this impact; the
  /// impulse taken was reduced towards the plastic one until it does not (docs/switching.md,
  /// "The energy rule").
  bool energy_limited = false;
};

/// What one unilateral contact did, over the whole run and over the window [window_start, t_end].
struct ContactStats {
  std::string name;          ///< the unilateral constraint
  std::string friction;      ///< its active friction constraint ("" none)
  struct Totals {
    double closed_time = 0.0;         ///< s in contact (any closed mode)
    double slip_time = 0.0;           ///< s sliding
    long lift_offs = 0, impacts = 0;  ///< impacts include accumulation closures
    long flights = 0;                 ///< flights begun: lift-offs and rebounds
    long slips = 0, sticks = 0, reversals = 0;
    double max_flight_height = 0.0;   ///< largest gap over the flights (m)
    double max_impact_velocity = 0.0; ///< largest approach speed −v_n⁻ at an impact (m/s)
    double slip_distance = 0.0;       ///< ∫ |v_t| dt over slip (m)
    double energy_impacts = 0.0;      ///< J lost in impacts (this contact's shares)
    double energy_friction = 0.0;     ///< J dissipated by sliding friction, ∫ μ_k λ_n |v_t| dt
    /// The largest penetration −gap (m, 0 if the gap never went negative) over the accepted
    /// steps' ends, the samples inside flights and the event states, in any mode, and when.
    double penetration_max = 0.0;
    double penetration_time = std::numeric_limits<double>::quiet_NaN();
    double flight_time = 0.0;         ///< s in flight, from the recorded flights (not closed_time)
  };
  Totals run, window;
  double gap_end = 0.0;     ///< the gap at the end of the run (m; negative: inside)
  double gap_tol_end = 0.0; ///< the gap's accuracy there (10 atol |grad g|_1 + rounding, m)
  /// Each flight: [start, end] and its largest gap (end = the run's end for an open flight).
  struct Flight {
    double start = 0.0, end = 0.0, max_gap = 0.0;
  };
  std::vector<Flight> flights;
};

struct SwitchingOptions {
  /// Accumulation (Zeno) rule: after an impact, a contact whose rebound would fly less than
  /// zeno_time (2 v_n⁺ / |a_n|, a_n its normal acceleration with every contact open) is closed
  /// instead (plastic, v_n⁺ = 0). The remaining bounces of a geometric sequence would last
  /// zeno_time / (1 − e) at most, which bounds the error in the time of rest.
  double zeno_time = 1e-6;
  /// Largest step while some contact is open or sliding (the sign changes of gaps and sliding
  /// velocities must not pair up inside one step); 0 = no limit beyond SimulationOptions::hmax.
  double flight_hmax = 0.0;
  double window_start = -std::numeric_limits<double>::infinity();  ///< for ContactStats::window
  long max_events = 1000000;         ///< switching events before the run fails
  int max_events_at_one_instant = 64;  ///< switches at one time before the run fails (no stall)
  /// When the mode decision is an LCP solved by Siconos: when two or more contacts are
  /// involved (a single contact's complementarity problem is solved in closed form), or always.
  enum class Lcp { several_contacts, always } lcp = Lcp::several_contacts;
  lcp::LcpSolver lcp_solver = lcp::LcpSolver::lemke;
};

struct SwitchingResult : SimulationResult {
  std::vector<ContactStats> contacts;  ///< one per active unilateral constraint, in model order
  std::vector<ContactMode> initial_modes;  ///< the modes decided at t0 (no events are recorded)
  std::vector<ContactEvent> events;
  long segments = 0;      ///< integrations between events
  long lcp_solves = 0;    ///< mode decisions solved by Siconos
  long late_roots = 0;    ///< gap crossings found by sampling a step (two in one step)
  /// Impacts where Newton's law would have created kinetic energy and the impulse was limited
  /// (ContactEvent::energy_limited), and the largest energy that would have been created (J).
  long energy_limited_impacts = 0;
  double energy_prevented_max = 0.0;
  double window_length = 0.0;
};

/// Called at t0 (t_prev == t) and after every accepted step; `modes` are the contacts' modes
/// during the step (in SwitchingResult::contacts order). Return false to stop.
using SwitchingObserver = std::function<bool(const StepView& v, const std::vector<ContactMode>& modes)>;

/// The names of the active unilateral constraints of a run (the contacts, in model order).
std::vector<std::string> unilateral_constraints(const Model& model,
                                                const std::vector<std::string>& active);

/// Integrates from (q0, qd0) like simulate(), switching the contacts of options'
/// active constraints that are unilateral (with their friction constraints). Needs the ODE form
/// (Form::ode) and projection; everything else as simulate(). Never throws.
SwitchingResult simulate_switching(const Model& model, const Eigen::VectorXd& q0,
                                   const Eigen::VectorXd& qd0, const SimulationOptions& options,
                                   const SwitchingOptions& switching,
                                   const SwitchingObserver& observer = {});

/// One impact resolved as simulate_switching() resolves it (for tests of the impact law): the
/// contacts of `active` that touch at (t, q) (gap within their accuracy) take part, and if one
/// approaches, Newton's law with Coulomb friction, the energy rule and the accumulation rule
/// (switching.zeno_time) give the velocities after. energy_change is ΔT = Λ·(v⁻ + v⁺)/2 of the
/// impulse (J; never above rounding); events has one row per approaching contact.
struct ImpactOutcome {
  bool ok = false;
  std::string message;
  Eigen::VectorXd qd_after;
  std::vector<ContactEvent> events;
  double energy_change = 0.0;
  long energy_limited = 0;  ///< 1 when the energy rule limited Newton's impulse
  /// Problems with a 2-D cone: Gauss-Seidel sweeps, problems handed to the fallback where it
  /// stalled, those it found no solution of, and its steps (contacts::LcpCounters).
  long cone_sweeps = 0, cone_fallbacks = 0, cone_unsolved = 0, cone_newton_steps = 0;
};
ImpactOutcome resolve_impact(const Model& model, const std::vector<std::string>& active, double t,
                             const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             const SimulationOptions& options = {},
                             const SwitchingOptions& switching = {});

/// Reactions and accelerations at one state with given contact modes (`modes` per unilateral
/// constraint of `active`, `slip_sign` ±1 per contact for slip), by the structured solve or
/// by the paper's dense [G; Dᵀ] system with the friction law replacing one ideality row
/// (ReactionMethod::compatibility). For tests of the two formulations.
ReactionResult switching_reactions(const Model& model, const std::vector<std::string>& active,
                                   const std::vector<ContactMode>& modes,
                                   const std::vector<int>& slip_sign, double t,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   ReactionMethod method, Kernel kernel = Kernel::fortran);

}  // namespace pcsim::mech
