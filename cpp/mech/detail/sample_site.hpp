// Internal: what a StepView of simulate() is made of. One implementation for the run's own
// observers (simulation.cpp's Run, on the integrating thread) and for steps recorded there and
// replayed on another thread (StepReplayer: issue 23's deferred observers), so that both give
// the same samples bit for bit: q and q̇ from the step's dense output, q̈, R and λ by one reaction
// solve at them, the model's derived quantities from those.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"

namespace pcsim::mech::detail {

/// What the samples of one run are computed with; shared (immutable) by the run and the replays
/// of its steps.
struct SampleSpec {
  const Model* model = nullptr;
  Kernel kernel = Kernel::fortran;
  Stabilization stabilization = Stabilization::none;
  double alpha = 0.0, beta = 0.0;
  ReactionMethod method = ReactionMethod::compatibility_structured;
  Form form = Form::ode;
  std::vector<int> active;
  // Dynamics::set_vanishing_limit of the run's sampling workspace.
  bool limit_on = false;
  int persistent_nullity = 0;
  double limit_switch = Dynamics::kLimitSwitch;
};

/// The sampling workspace of one run (or of one replayer) and the step it is looking at.
class SampleSite {
 public:
  SampleSite(const Model& model, const SimulationOptions& opt, std::vector<int> active);
  explicit SampleSite(std::shared_ptr<const SampleSpec> spec);

  Dynamics& dynamics() { return dyn_; }
  const ActiveSet& set() const { return set_; }
  const std::shared_ptr<const SampleSpec>& spec() const { return spec_; }
  int ny() const { return spec_->form == Form::ode ? 2 * n_ : 4 * n_; }

  /// Dynamics::set_vanishing_limit on the workspace, kept in the spec for the replays.
  void set_vanishing_limit(bool on, int persistent_nullity, double switch_ratio);

  /// The state at t with reactions and derived quantities, into `out` (its storage is reused).
  void fill(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Sample& out);

  /// The step being observed: the integrator's (step == nullptr at the initial state) ...
  void look_at(const StepInfo* step, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  /// ... or a recorded one (the record must outlive the observation).
  void look_at(const StepRecord& record);
  /// A view of the step looked at (valid while it is).
  StepView view() const;

 private:
  static const Sample& view_at(const void* self, double s);
  static void view_state(const void* self, double s, Eigen::VectorXd& q, Eigen::VectorXd& qd);
  static void view_derived(const void* self, double s, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                           const Eigen::VectorXd& R, const Eigen::VectorXd& lambda,
                           Eigen::VectorXd& out);
  static bool view_record(const void* self, StepRecord& out);

  double clamp(double s) const;
  void dense(double s);  // the step's polynomial at s into dense_
  void state_in_step(double s, Eigen::VectorXd& q, Eigen::VectorXd& qd);
  const Sample& sample_in_step(double s);

  std::shared_ptr<const SampleSpec> spec_;
  const Model& model_;
  ActiveSet set_;
  Dynamics dyn_;
  int n_, s_;
  // The step looked at.
  const StepInfo* live_ = nullptr;
  const DenseCopy* copy_ = nullptr;
  bool has_step_ = false;
  double t_prev_ = 0.0, t_ = 0.0;
  Eigen::VectorXd q_, qd_;                 // the state at t_ (live: a copy)
  const Eigen::VectorXd* qp_ = &q_;        // recorded: the record's own
  const Eigen::VectorXd* qdp_ = &qd_;
  // Samples are cached by time within a step: observers often ask for the same instant (the
  // step end) more than once, and each sample costs a full reaction solve.
  Sample cache_;
  bool cache_valid_ = false;
  Eigen::VectorXd dense_, dq_, dqd_;
};

}  // namespace pcsim::mech::detail
