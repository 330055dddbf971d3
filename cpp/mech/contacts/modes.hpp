// The mode logic of the switching contacts (issue 12): at an event (or at t0) the impact, the
// decision of the contacts' modes (closed or open, sticking or sliding) by their
// complementarity problem at acceleration level, the consistency check of the decided set,
// the projection onto it, and the events of the mode changes.
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/contacts/contact_set.hpp"
#include "mech/contacts/impact.hpp"
#include "mech/contacts/lcp_problem.hpp"
#include "mech/projection.hpp"
#include "mech/simulation.hpp"

namespace pcsim::mech::contacts {

class ModeLogic {
 public:
  ModeLogic(const ContactSet& cs, const SimulationOptions& opt, const SwitchingOptions& sw);

  /// The full transition at an event (or at t0): impact, modes, consistency, projection, and
  /// the events of the mode changes (appended to `events`; none at t0 but impacts). Returns
  /// false on failure (message()).
  bool transition(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd, const Config& before,
                  const Solved* reactions_before, Config& after, std::vector<ContactEvent>& events,
                  bool initial);

  /// The minimum-norm projection of (q, q̇) onto the imposed rows of L (project_state; with
  /// unanchored friction rows: positions onto the others, then velocities onto all).
  ModelIssue project(const Layout& L, double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                     double& dq, double& dv, std::string& msg);

  /// A holonomic friction constraint (rolling: s + r φ = const) holds its position-level
  /// constant only until its contact first leaves stick: after a slip or a flight the contact
  /// point has moved, and sticking again means v_t = 0 from the new position on. Such an
  /// unanchored friction row is projected at the velocity level only, and its Φ is not a
  /// residual.
  bool position_level(int constraint) const;

  /// The reactions of configuration cfg (layout L) at a state, by the run's reaction method.
  ModelIssue reactions(const Layout& L, const Config& cfg, double t, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& qd, Solved& out);

  const std::string& message() const { return message_; }
  const LcpCounters& lcp_counters() const { return lcp_counters_; }
  const ImpactCounters& impact_counters() const { return impact_.counters(); }

 private:
  bool decide(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg,
              bool force_lcp);
  bool mark_implied(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg);
  int check(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg);

  const ContactSet& cs_;
  Kernel kernel_;
  double projection_tol_;
  ReactionMethod method_;
  SwitchingOptions::Lcp lcp_policy_;
  lcp::LcpSolver lcp_solver_;
  Dynamics aux_dyn_;
  LcpCounters lcp_counters_;
  ImpactLaw impact_;
  ImpulseShares shares_;
  std::vector<char> anchored_;  ///< per contact: its friction row still holds its position constant
  ProjectionWork pw_;
  std::string message_;
};

}  // namespace pcsim::mech::contacts
