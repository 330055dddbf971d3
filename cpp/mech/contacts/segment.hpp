// The integration adapter of a switching run (issue 12): one segment between events with a
// fixed configuration of contact modes. It gives the integrator the right-hand side (the
// reactions of the segment's set, sliding friction included) and the event functions (lift-off,
// the friction cone, a sliding velocity through zero, a gap closing), finds the roots a step
// hides (a gap that dips and comes back within one step), projects drift, tracks residuals,
// penetrations and the contacts' statistics, and serves the step observer's samples.
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/contacts/contact_set.hpp"
#include "mech/contacts/modes.hpp"
#include "mech/contacts/switching.hpp"
#include "ode/integrate.hpp"

namespace pcsim::mech::contacts {

/// An event function of a segment.
struct EventFn {
  int c;
  /// surfaced: a flight that started inside the surface (gap below −its rounding) came out
  /// of it; its landing threshold, taken from the start, is then reset to the surface.
  enum Kind { lift_off, cone_plus, cone_minus, sliding, gap, surfaced } kind;
};

/// How the last segment's integration ended, beyond the integrator's own result.
struct SegmentOutcome {
  bool late = false;                 ///< a root found inside a step (state at late_t)
  double late_t = 0.0;
  Eigen::VectorXd late_q, late_qd;
  ModelIssue projection_issue = ModelIssue::none;  ///< the drift projection failed
  std::string projection_message;
  bool model_failed = false;         ///< the right-hand side could not be evaluated
  std::string model_failure;
  bool stopped = false;              ///< the observer asked to stop
  std::string observer_error;        ///< the observer threw
  double t = 0.0;                    ///< the last state observed
  Eigen::VectorXd q, qd;
};

class Segment {
 public:
  Segment(const ContactSet& cs, ModeLogic& modes, const SimulationOptions& opt,
          const SwitchingOptions& sw, SwitchingResult& res, const SwitchingObserver& observer);

  /// The segment's configuration (set before each integration). The event functions start on
  /// their positive side by construction of the modes, often exactly at zero (a gap or a sliding
  /// velocity that has just opened). The kernels take the sign of a function that is exactly
  /// zero at the start from the end of the first step, which would hide a root inside that
  /// step (a flight or a slip shorter than the step). Each function therefore carries a tiny
  /// positive offset (the rounding of its own gap or sliding velocity, ContactSet::gap_round,
  /// 1e-12 of the forces), so its sign is known from the start; roots are located that far on
  /// the other side of zero. `grazing`: the previous event of a flying contact changed nothing
  /// (its gap returned to zero without approach velocity and the contact still separates: it
  /// grazes the surface at the integration's accuracy); its next landing is then taken only
  /// below -gap_tol, so the run progresses instead of switching at every rounding-level dip.
  void configure(const Config& cfg, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                 bool grazing = false);
  const Layout& layout() const { return layout_; }

  /// Before an integration: arms the event functions of the configuration.
  void begin();
  const std::vector<EventFn>& event_functions() const { return fns_; }
  const SegmentOutcome& outcome() const { return out_; }

  /// The shortest predicted flight of the contacts that have just opened (gap within the
  /// tolerance, moving apart): 2 v_n / |a_n| with a_n from the segment's accelerations; +inf if
  /// none is pulled back.
  double shortest_flight(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);

  // The integrator's callbacks.
  bool rhs(double t, const double* y, double* out);
  bool events(double t, const double* y, double* g);
  StepAction on_step(StepInfo& step);

  /// Shows the state at t0 (t_prev == t) to the observer; false: stop.
  bool observe(const StepInfo* step, double t_prev, double t, const Eigen::VectorXd& q,
               const Eigen::VectorXd& qd);
  /// The deepest penetration of every contact (any mode; or contact `only`), into the run's and
  /// window's totals and into the position residual: a unilateral constraint's violation is a
  /// constraint residual like any other (issue 19: "max constraint residual 0" was printed for
  /// a ball 4.8e-6 m inside the floor).
  void track_penetration(double t, const Eigen::VectorXd& q, int only = -1);
  void track_residuals(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);

 private:
  std::vector<EventFn> make_event_functions() const;
  void fill_sample(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Sample& out);
  static const Sample& view_at(const void* self, double s);
  const Sample& sample_in_step(double s);
  void dense_at(const StepInfo& step, double s, Eigen::VectorXd& q, Eigen::VectorXd& qd);
  void account(const StepInfo& step, double a, double b);
  bool consistent_enough(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);

  const ContactSet& cs_;
  ModeLogic& modes_logic_;
  const Model& model_;
  const SimulationOptions& opt_;
  const SwitchingOptions& sw_;
  SwitchingResult& res_;
  const SwitchingObserver& observer_;
  int n_;
  ReactionMethod method_;
  Config cfg_;
  Layout layout_;
  std::vector<EventFn> fns_;
  std::vector<double> gap_offset_, gs_, ys_;
  std::vector<double> eps_gap_, eps_vel_;  ///< per contact (ContactSet::gap_round, velocity_round)
  double eps_force_ = 0.0;
  std::vector<ContactMode> modes_;
  Dynamics rhs_dyn_, sample_dyn_, event_dyn_;
  Solved rhs_solved_, ev_solved_, sample_solved_;
  Eigen::VectorXd q_, qd_, q_e_, qd_e_, dense_, dq_, dqd_, sq_, sqd_, lambda_set_;
  const StepInfo* step_ = nullptr;
  double step_end_ = 0.0;
  Sample cache_;
  bool cache_valid_ = false;
  SegmentOutcome out_;
};

}  // namespace pcsim::mech::contacts
