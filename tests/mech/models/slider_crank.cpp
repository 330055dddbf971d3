// Validation model: a slider-crank in redundant coordinates q = (phi1, x2, y2, phi2, x3), n = 5:
// crank (uniform rod, mass m1, length l1) turning about the origin at angle phi1; connecting rod
// (mass m2, length l2, centroidal inertia m2 l2²/12) with centre (x2, y2) and angle phi2;
// slider (mass m3) at (x3, 0). Gravity −g along y; constant drive torque tau on the crank;
// viscous slider damping c (Rayleigh F = ½ c ẋ3²). Four holonomic joint constraints leave one
// degree of freedom, so D (5 x 1) is non-trivial and changes with q. Two extra constraints exist
// to test the rank handling: "B_y_copy" (= 2 × B_y, redundant) and "B_y_shifted" (B_y − 0.1,
// contradicts B_y).
#include <cmath>

#include "common/error.hpp"
#include "mech/models/registry.hpp"

namespace pcsim::mech {

namespace {

struct SliderCrank {
  double m1, l1, m2, l2, m3, grav, tau, c;
  static constexpr int kCoordinates = 5;  // optional: fixed-size (faster) AD

  std::string name() const { return "slider_crank"; }
  std::vector<std::string> coordinates() const { return {"phi1", "x2", "y2", "phi2", "x3"}; }
  std::vector<ConstraintInfo> constraints() const {
    return {{"A_x", ConstraintKind::holonomic, false},
            {"A_y", ConstraintKind::holonomic, false},
            {"B_x", ConstraintKind::holonomic, false},
            {"B_y", ConstraintKind::holonomic, false},
            {"B_y_copy", ConstraintKind::holonomic, false, /*active_by_default=*/false},
            {"B_y_shifted", ConstraintKind::holonomic, false, /*active_by_default=*/false}};
  }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    const double J1 = m1 * l1 * l1 / 3.0;   // crank about the pivot
    const double J2 = m2 * l2 * l2 / 12.0;  // rod about its centre
    return 0.5 * J1 * qd[0] * qd[0] + 0.5 * m2 * (qd[1] * qd[1] + qd[2] * qd[2]) +
           0.5 * J2 * qd[3] * qd[3] + 0.5 * m3 * qd[4] * qd[4];
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    using std::sin;
    return grav * (m1 * 0.5 * l1 * sin(q[0]) + m2 * q[2]);
  }
  template <class S> S dissipation(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * c * qd[4] * qd[4];
  }
  template <class S> VecX<S> applied_forces(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    VecX<S> Qa = VecX<S>::Zero(5);
    Qa[0] = S(tau);
    return Qa;
  }
  template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const {
    using std::cos;
    using std::sin;
    const double h = 0.5 * l2;
    switch (i) {
      case 0: return q[1] - h * cos(q[3]) - l1 * cos(q[0]);           // A_x
      case 1: return q[2] - h * sin(q[3]) - l1 * sin(q[0]);           // A_y
      case 2: return q[1] + h * cos(q[3]) - q[4];                      // B_x
      case 3: return q[2] + h * sin(q[3]);                             // B_y
      case 4: return 2.0 * (q[2] + h * sin(q[3]));                     // B_y_copy
      default: return q[2] + h * sin(q[3]) - 0.1;                      // B_y_shifted
    }
  }
};

}  // namespace

ModelParameters slider_crank_defaults() {
  return {{"m1", 1.0}, {"l1", 0.2}, {"m2", 2.0}, {"l2", 0.6}, {"m3", 1.5},
          {"g", 9.81}, {"tau", 1.0}, {"c", 0.5}};
}

std::shared_ptr<const Model> create_slider_crank(const ModelParameters& parameters) {
  const ParameterReader p("slider_crank", slider_crank_defaults(), parameters);
  if (!(p.get("l2") > p.get("l1"))) {
    throw InputError("model 'slider_crank': parameter 'l2' must exceed 'l1' (the crank turns)");
  }
  return make_model(SliderCrank{p.positive("m1"), p.positive("l1"), p.positive("m2"),
                                p.positive("l2"), p.positive("m3"), p.get("g"), p.get("tau"),
                                p.get("c")});
}

}  // namespace pcsim::mech
