// The impact law of the switching contacts (issue 12, issue 19): Newton's law at impulse level
// with Coulomb-bounded tangential impulses from the contacts' complementarity problem, the
// energy rule (an impact never creates kinetic energy) and the accumulation (Zeno) rule.
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/contacts/contact_set.hpp"
#include "mech/contacts/lcp_problem.hpp"

namespace pcsim::mech::contacts {

/// What an impact leaves for the mode changes of its instant: the closed contacts that took
/// part without approaching (their impulses, reported with their own switch) and their shares
/// of the energy lost (booked with an event of the instant, or of the next one).
struct ImpulseShares {
  std::vector<char> impulsed;  ///< per contact: took part in this instant's impact without approaching
  std::vector<double> impulse_n, impulse_t;
  std::vector<double> pending_loss;  ///< per contact, until booked (survives the instant at t0)
  /// A new instant: no impulses yet (pending losses stay).
  void begin_instant(int nc) {
    impulsed.assign(nc, 0);
    impulse_n.assign(nc, 0.0);
    impulse_t.assign(nc, 0.0);
  }
};

/// The energy rule's account over a run.
struct ImpactCounters {
  long energy_limited = 0;            ///< impacts whose impulse the energy rule limited
  double energy_prevented_max = 0.0;  ///< the largest ΔT > 0 Newton's impulse would have made
  double last_energy_change = 0.0;    ///< ΔT of the last impact (J, <= rounding)
};

class ImpactLaw {
 public:
  /// `d` is the workspace for the contacts' inertia; zeno_time as SwitchingOptions::zeno_time.
  ImpactLaw(const ContactSet& cs, Dynamics& d, double zeno_time, LcpSettings lcp,
            LcpCounters& lcp_counters)
      : cs_(cs), d_(d), zeno_time_(zeno_time), lcp_(lcp), lcp_counters_(lcp_counters) {}

  /// Resolves an impact at (t, q, qd) if a touching contact approaches: Newton's law with the
  /// impulses of the compatibility equations at impulse level (Coulomb-bounded tangential
  /// impulses), the accumulation rule, the energy rule, and the events (appended; hit[c] = 1
  /// for each contact that had one). qd is updated. Returns false on failure (`message`).
  bool resolve(double t, const Eigen::VectorXd& q, Eigen::VectorXd& qd, const Config& before,
               std::vector<ContactEvent>& events, std::vector<char>& hit, ImpulseShares& shares,
               std::string& message);

  const ImpactCounters& counters() const { return counters_; }

 private:
  const ContactSet& cs_;
  Dynamics& d_;
  double zeno_time_;
  LcpSettings lcp_;
  LcpCounters& lcp_counters_;
  ImpactCounters counters_;
};

}  // namespace pcsim::mech::contacts
