#include "mech/detail/sample_site.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pcsim::mech::detail {

namespace {

std::shared_ptr<const SampleSpec> make_spec(const Model& model, const SimulationOptions& opt,
                                            std::vector<int> active) {
  auto spec = std::make_shared<SampleSpec>();
  spec->model = &model;
  spec->kernel = opt.kernel;
  spec->stabilization = opt.stabilization;
  spec->alpha = opt.baumgarte_alpha;
  spec->beta = opt.baumgarte_beta;
  spec->method = opt.reaction_method;
  spec->form = opt.form;
  spec->active = std::move(active);
  return spec;
}

}  // namespace

SampleSite::SampleSite(const Model& model, const SimulationOptions& opt, std::vector<int> active)
    : SampleSite(make_spec(model, opt, std::move(active))) {}

SampleSite::SampleSite(std::shared_ptr<const SampleSpec> spec)
    : spec_(std::move(spec)),
      model_(*spec_->model),
      set_(ActiveSet::of(model_, spec_->active)),
      dyn_(model_, spec_->kernel, spec_->stabilization, spec_->alpha, spec_->beta),
      n_(model_.n()),
      s_(set_.size()) {
  // Large models with sparse structure: M and g as sparse values on the per-step paths.
  dyn_.sparse_evaluation = true;
  dyn_.set_vanishing_limit(spec_->limit_on, spec_->persistent_nullity, spec_->limit_switch);
}

void SampleSite::set_vanishing_limit(bool on, int persistent_nullity, double switch_ratio) {
  dyn_.set_vanishing_limit(on, persistent_nullity, switch_ratio);
  auto spec = std::make_shared<SampleSpec>(*spec_);
  spec->limit_on = on;
  spec->persistent_nullity = persistent_nullity;
  spec->limit_switch = switch_ratio;
  spec_ = std::move(spec);
}

void SampleSite::fill(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Sample& out) {
  out.t = t;
  out.q = q;
  out.qd = qd;
  ModelIssue e = dyn_.evaluate(set_, t, q, qd);
  if (e == ModelIssue::none) e = dyn_.solve(spec_->method);
  if (e == ModelIssue::none) {
    out.qdd = dyn_.qdd;
    out.R = dyn_.R;
    out.lambda = dyn_.lambda;
  } else {
    out.qdd = Eigen::VectorXd::Constant(n_, std::nan(""));
    out.R = out.qdd;
    out.lambda = Eigen::VectorXd::Constant(s_, std::nan(""));
  }
  model_.derived_with_multipliers(t, q, qd, out.qdd, out.R, set_.rows(), out.lambda, out.derived);
  out.residual_pos = dyn_.position_residual(t, q);
  out.residual_vel = dyn_.velocity_residual(qd);
}

void SampleSite::look_at(const StepInfo* step, double t, const Eigen::VectorXd& q,
                         const Eigen::VectorXd& qd) {
  live_ = step;
  copy_ = nullptr;
  has_step_ = step != nullptr;
  t_prev_ = step ? step->t_prev : t;
  t_ = t;
  q_ = q;
  qd_ = qd;
  qp_ = &q_;
  qdp_ = &qd_;
  cache_valid_ = false;
}

void SampleSite::look_at(const StepRecord& record) {
  live_ = nullptr;
  copy_ = &record.dense;
  has_step_ = !record.dense.empty();
  t_prev_ = record.t_prev;
  t_ = record.t;
  qp_ = &record.q;
  qdp_ = &record.qd;
  cache_valid_ = false;
}

StepView SampleSite::view() const {
  StepView view;
  view.t_prev = t_prev_;
  view.t = t_;
  view.impl_ = this;
  view.impl_at_ = &SampleSite::view_at;
  view.impl_state_ = &SampleSite::view_state;
  view.impl_derived_ = &SampleSite::view_derived;
  view.impl_record_ = &SampleSite::view_record;
  return view;
}

// Past the step's end, at the initial state, or on a step of zero length: the state at its end.
double SampleSite::clamp(double s) const {
  return !has_step_ || s >= t_ || t_ == t_prev_ ? t_ : s;
}

void SampleSite::dense(double s) {
  dense_.resize(ny());
  if (live_)
    live_->dense(std::max(s, t_prev_), dense_.data());
  else
    copy_->dense(std::max(s, t_prev_), dense_.data());
}

void SampleSite::state_in_step(double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  s = clamp(s);
  if (s == t_) {
    q = *qp_;
    qd = *qdp_;
    return;
  }
  dense(s);
  q = dense_.head(n_);
  qd = dense_.segment(n_, n_);
}

const Sample& SampleSite::sample_in_step(double s) {
  s = clamp(s);
  if (cache_valid_ && cache_.t == s) return cache_;
  if (s == t_) {
    fill(t_, *qp_, *qdp_, cache_);
  } else {
    dense(s);
    dq_ = dense_.head(n_);
    dqd_ = dense_.segment(n_, n_);
    fill(s, dq_, dqd_, cache_);
  }
  cache_valid_ = true;
  return cache_;
}

const Sample& SampleSite::view_at(const void* self, double s) {
  return const_cast<SampleSite*>(static_cast<const SampleSite*>(self))->sample_in_step(s);
}

void SampleSite::view_state(const void* self, double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  const_cast<SampleSite*>(static_cast<const SampleSite*>(self))->state_in_step(s, q, qd);
}

void SampleSite::view_derived(const void* self, double s, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                              const Eigen::VectorXd& R, const Eigen::VectorXd& lambda,
                              Eigen::VectorXd& out) {
  const auto& site = *static_cast<const SampleSite*>(self);
  site.model_.derived_with_multipliers(s, q, qd, qdd, R, site.set_.rows(), lambda, out);
}

bool SampleSite::view_record(const void* self, StepRecord& out) {
  const auto& site = *static_cast<const SampleSite*>(self);
  out.t_prev = site.t_prev_;
  out.t = site.t_;
  out.q = *site.qp_;
  out.qd = *site.qdp_;
  if (site.live_ && site.has_step_)
    site.live_->copy_dense(out.dense);
  else if (site.copy_)
    out.dense = *site.copy_;
  else
    out.dense.eval_ = nullptr;  // empty (its storage kept for the next record)
  out.spec = site.spec_;
  return true;
}

}  // namespace pcsim::mech::detail

namespace pcsim::mech {

StepReplayer::StepReplayer() = default;
StepReplayer::~StepReplayer() = default;

bool StepReplayer::replay(const StepRecord& record, const StepObserver& observer) {
  if (!site_ || site_->spec() != record.spec)
    site_ = std::make_unique<detail::SampleSite>(record.spec);
  site_->look_at(record);
  return observer(site_->view());
}

}  // namespace pcsim::mech
