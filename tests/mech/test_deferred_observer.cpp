// Issue 23's deferred observers (mech/deferred_observer.hpp): an observer that runs on a thread
// of its own, on steps recorded by the integrating thread and replayed there, sees exactly what
// it would have seen in place. The oracle is the in-place observation of the same run: every
// value it reads (samples inside and at the end of each step, the dense state, the derived
// quantities) is compared bit for bit, on the explicit method and on Radau (the two dense-output
// copies), in the ODE and DAE forms, with and without projection. Then: a failure of the
// observer stops the run and is reported; a view that cannot be recorded is observed in place
// after the steps before it; StepInfo::copy_dense gives the step's own polynomial.
#define BOOST_TEST_MODULE mech_deferred_observer
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/format.hpp"
#include "mech/deferred_observer.hpp"
#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"

using namespace pcsim;
using namespace pcsim::mech;

namespace {

// Slider-crank state consistent with its four joints at crank angle phi1 (as test_simulation).
void slider_crank_state(double phi1, double w1, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  const ModelParameters p = default_parameters("slider_crank");
  const double l1 = p.at("l1"), l2 = p.at("l2");
  const double ax = l1 * std::cos(phi1), ay = l1 * std::sin(phi1);
  const double x3 = ax + std::sqrt(l2 * l2 - ay * ay);
  const double phi2 = std::atan2(-ay, x3 - ax);
  q.resize(5);
  q << phi1, 0.5 * (ax + x3), 0.5 * ay, phi2, x3;
  qd = Eigen::VectorXd::Zero(5);
  qd[0] = w1;
}

// Everything an observer can read of a step, flattened: the samples at the step's end, at three
// inner points (twice each: the cache), the dense state and the derived quantities there.
struct Reader {
  std::vector<double> seen;
  long steps = 0;
  void put(const Eigen::VectorXd& v) { seen.insert(seen.end(), v.data(), v.data() + v.size()); }
  void put(const Sample& s) {
    seen.push_back(s.t);
    put(s.q);
    put(s.qd);
    put(s.qdd);
    put(s.R);
    put(s.lambda);
    put(s.derived);
    seen.push_back(s.residual_pos);
    seen.push_back(s.residual_vel);
  }
  bool operator()(const StepView& v) {
    ++steps;
    seen.push_back(v.t_prev);
    seen.push_back(v.t);
    put(v.sample(v.t));
    for (double f : {0.25, 0.5, 0.9}) {
      const double s = v.t_prev + f * (v.t - v.t_prev);
      put(v.sample(s));
      put(v.at(s));
      Eigen::VectorXd q, qd, out;
      v.state(s, q, qd);
      put(q);
      put(qd);
      const Sample& x = v.sample(s);
      v.derived(s, x.q, x.qd, x.qdd, x.R, x.lambda, out);
      put(out);
    }
    put(v.sample(v.t + 1.0));  // past the end: the end
    return true;
  }
};

bool bitwise_equal(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

SimulationOptions crank_options(OdeMethod method, Form form, Stabilization stab) {
  SimulationOptions o;
  o.t_end = 0.4;
  o.rtol = o.atol = 1e-8;
  o.method = method;
  o.form = form;
  o.stabilization = stab;
  o.active_constraints = {"A_x", "A_y", "B_x", "B_y"};
  return o;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_deferred_observer_sees_bit_for_bit_what_it_sees_in_place) {
  const auto model = create_model("slider_crank", {});
  Eigen::VectorXd q0, qd0;
  slider_crank_state(0.3, 20.0, q0, qd0);
  struct Variant { OdeMethod method; Form form; Stabilization stab; const char* what; };
  for (const Variant& var : {Variant{OdeMethod::explicit_rk, Form::ode, Stabilization::none, "explicit"},
                             Variant{OdeMethod::radau, Form::ode, Stabilization::projection, "radau, projection"},
                             Variant{OdeMethod::radau, Form::dae, Stabilization::projection, "radau, DAE form"}}) {
    BOOST_TEST_CONTEXT(var.what) {
      const SimulationOptions o = crank_options(var.method, var.form, var.stab);
      Reader here;
      const SimulationResult r1 = simulate(*model, q0, qd0, o, [&](const StepView& v) { return here(v); });
      BOOST_TEST((r1.status == SimulationStatus::success));
      Reader there;
      DeferredObserver deferred([&](const StepView& v) { return there(v); });
      const SimulationResult r2 = simulate(*model, q0, qd0, o, [&](const StepView& v) { return deferred.push(v); });
      deferred.finish();
      BOOST_TEST((r2.status == SimulationStatus::success));
      BOOST_TEST(deferred.error().empty());
      BOOST_TEST(there.steps == here.steps);
      BOOST_TEST(here.steps > 10);
      BOOST_TEST(bitwise_equal(here.seen, there.seen));
      // The same run with the observer's thread switched off (threaded = false): in place.
      Reader off;
      DeferredObserver in_place([&](const StepView& v) { return off(v); }, false);
      BOOST_TEST(!in_place.threaded());
      simulate(*model, q0, qd0, o, [&](const StepView& v) { return in_place.push(v); });
      in_place.finish();
      BOOST_TEST(bitwise_equal(here.seen, off.seen));
    }
  }
  // (On a machine with one hardware thread the deferred observer runs in place, and the
  // comparison above proves nothing about the replay: say so.)
  if (std::thread::hardware_concurrency() < 2)
    BOOST_TEST_MESSAGE("one hardware thread: the deferred observer ran in place");
}

namespace {
// The step end times of the run observed in place (index 0: the initial state), and the latest
// time a run whose deferred observer fails at call k may reach: the integrating thread is at
// most the ring's capacity of steps ahead of the observer, and learns of the failure at its
// next step.
std::vector<double> step_times(const Model& model, const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0,
                               const SimulationOptions& o) {
  std::vector<double> t;
  simulate(model, q0, qd0, o, [&](const StepView& v) {
    t.push_back(v.t);
    return true;
  });
  return t;
}
double latest_stop(const std::vector<double>& times, std::size_t failing_call) {
  return times.at(std::min(times.size() - 1, failing_call + DeferredObserver::kCapacity + 1));
}
}  // namespace

BOOST_AUTO_TEST_CASE(an_observer_that_throws_stops_the_run_and_says_why) {
  const auto model = create_model("slider_crank", {});
  Eigen::VectorXd q0, qd0;
  slider_crank_state(0.3, 20.0, q0, qd0);
  // Long enough for thousands of steps, so that the run must stop long before t_end.
  SimulationOptions o = crank_options(OdeMethod::explicit_rk, Form::ode, Stabilization::none);
  o.t_end = 20.0;
  const std::vector<double> times = step_times(*model, q0, qd0, o);
  BOOST_REQUIRE(times.size() > 4 * DeferredObserver::kCapacity);
  for (bool threaded : {true, false}) {
    long calls = 0;
    DeferredObserver deferred(
        [&](const StepView& v) {
          if (++calls == 5) throw std::runtime_error("disk full");
          return true;
        },
        threaded);
    const SimulationResult r = simulate(*model, q0, qd0, o, [&](const StepView& v) { return deferred.push(v); });
    deferred.finish();
    BOOST_TEST((r.status == SimulationStatus::stopped_by_observer));
    BOOST_TEST(r.t <= latest_stop(times, 5));
    if (!threaded) BOOST_TEST(r.t == times[4]);  // in place: at the failing step itself
    BOOST_TEST(deferred.error() == "the step observer threw: disk full");
    BOOST_TEST(calls == 5);  // nothing observed after the failure
    BOOST_TEST(!deferred.push(StepView{}));  // and nothing more is taken
  }
}

BOOST_AUTO_TEST_CASE(an_observer_that_returns_false_stops_the_run_and_names_the_time) {
  const auto model = create_model("slider_crank", {});
  Eigen::VectorXd q0, qd0;
  slider_crank_state(0.3, 20.0, q0, qd0);
  SimulationOptions o = crank_options(OdeMethod::explicit_rk, Form::ode, Stabilization::none);
  o.t_end = 20.0;
  const std::vector<double> times = step_times(*model, q0, qd0, o);
  std::size_t call = 0, stopped_call = 0;
  double stopped_at = 0.0;
  DeferredObserver deferred([&](const StepView& v) {
    ++call;
    if (v.t < 0.1) return true;
    stopped_at = v.t;
    stopped_call = call;
    return false;
  });
  const SimulationResult r = simulate(*model, q0, qd0, o, [&](const StepView& v) { return deferred.push(v); });
  deferred.finish();
  BOOST_TEST((r.status == SimulationStatus::stopped_by_observer));
  BOOST_TEST(stopped_at >= 0.1);
  BOOST_TEST(r.t <= latest_stop(times, stopped_call));
  BOOST_TEST(deferred.error() == "the step observer stopped observing at t = " + format_significant(stopped_at, 9));
}

namespace {
// A view that cannot be recorded (no impl_record_), as the switching driver's.
Sample g_unrecorded;
const Sample& unrecorded_at(const void*, double) { return g_unrecorded; }
}  // namespace

BOOST_AUTO_TEST_CASE(a_view_that_cannot_be_recorded_is_observed_in_place_after_the_steps_before_it) {
  const auto model = create_model("slider_crank", {});
  Eigen::VectorXd q0, qd0;
  slider_crank_state(0.3, 20.0, q0, qd0);
  const SimulationOptions o = crank_options(OdeMethod::explicit_rk, Form::ode, Stabilization::none);
  std::vector<double> order;
  std::thread::id observer_thread;
  const std::thread::id here = std::this_thread::get_id();
  DeferredObserver deferred([&](const StepView& v) {
    order.push_back(v.t);
    if (v.t == 99.0) observer_thread = std::this_thread::get_id();
    return true;
  });
  double last = 0.0;
  simulate(*model, q0, qd0, o, [&](const StepView& v) {
    last = v.t;
    return deferred.push(v);
  });
  StepView odd;
  odd.t_prev = odd.t = 99.0;
  odd.impl_at_ = &unrecorded_at;
  StepRecord record;
  BOOST_TEST(!odd.record(record));
  BOOST_TEST(deferred.push(odd));
  deferred.finish();
  BOOST_REQUIRE(order.size() >= 2u);
  BOOST_TEST(order[order.size() - 2] == last);  // every recorded step first
  BOOST_TEST(order.back() == 99.0);
  BOOST_TEST((observer_thread == here));  // observed in place
}

BOOST_AUTO_TEST_CASE(a_copy_of_the_dense_output_is_the_step_polynomial_bit_for_bit) {
  // Both integrators and both kernels: the copy, evaluated after the step callback has
  // returned (the integrator has overwritten its work array since), against the values the
  // step's own dense() gave inside the callback.
  OdeProblem p;
  p.n = 3;
  p.rhs = [](double t, const double* y, double* f) {
    f[0] = y[1];
    f[1] = -y[0] + 0.1 * std::sin(3.0 * t);
    f[2] = -2.0 * y[2] + y[0] * y[1];
    return true;
  };
  const Eigen::Vector3d y0(1.0, 0.0, 0.5);
  for (OdeMethod method : {OdeMethod::explicit_rk, OdeMethod::radau}) {
    for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
      OdeOptions oo;
      oo.kernel = kernel;
      oo.rtol = oo.atol = 1e-9;
      std::vector<DenseCopy> copies;
      std::vector<std::vector<double>> inside;
      std::vector<std::pair<double, double>> spans;
      const OdeResult r = ode_integrate(p, 0.0, y0, 20.0, oo, method, [&](StepInfo& s) {
        if (!(s.t > s.t_prev)) return StepAction::proceed;
        copies.emplace_back();
        s.copy_dense(copies.back());
        spans.emplace_back(s.t_prev, s.t);
        std::vector<double> v(9);
        for (int k = 0; k < 3; ++k) s.dense(s.t_prev + (k + 1) * 0.25 * (s.t - s.t_prev), v.data() + 3 * k);
        inside.push_back(v);
        return StepAction::proceed;
      });
      BOOST_TEST((r.status == OdeStatus::success));
      BOOST_REQUIRE(copies.size() > 10u);
      bool same = true;
      for (std::size_t i = 0; i < copies.size(); ++i) {
        BOOST_TEST(copies[i].n() == 3);
        std::vector<double> v(9);
        for (int k = 0; k < 3; ++k)
          copies[i].dense(spans[i].first + (k + 1) * 0.25 * (spans[i].second - spans[i].first), v.data() + 3 * k);
        same = same && std::memcmp(v.data(), inside[i].data(), 9 * sizeof(double)) == 0;
      }
      BOOST_TEST(same);
    }
  }
}
