// Validation model: a disk (mass m, radius r, inertia J about its centre) on an incline of angle
// alpha. Coordinates in the incline frame: s along the slope (positive downhill), w the height of
// the centre over the plane, phi the rotation (positive when rolling downhill). Constraints:
// "contact" w − r = 0 (holonomic) and "rolling" ṡ − r φ̇ = 0 (velocity form). Closed forms
// (both active): s̈ = g sin α / (1 + J/(m r²)), normal reaction R_w = m g cos α, friction
// R_s = −J s̈ / r² (uphill), R_φ = −r R_s.
#include <cmath>

#include "mech/models/registry.hpp"

namespace pcsim::mech {

namespace {

struct RollingDisk {
  double m, r, J, alpha, grav;
  static constexpr int kCoordinates = 3;  // optional: fixed-size (faster) AD

  std::string name() const { return "rolling_disk"; }
  std::vector<std::string> coordinates() const { return {"s", "w", "phi"}; }
  std::vector<ConstraintInfo> constraints() const {
    return {{"contact", ConstraintKind::holonomic, true},
            {"rolling", ConstraintKind::velocity, true}};
  }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * J * qd[2] * qd[2];
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    return m * grav * (q[1] * std::cos(alpha) - q[0] * std::sin(alpha));
  }
  template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const {
    return q[1] - r;  // contact
  }
  template <class S>
  void velocity_form(int i, const VecX<S>& q, const S& t, VecX<S>& g_row, S& g0) const {
    g_row[0] = S(1.0);  // rolling: ṡ − r φ̇ = 0
    g_row[1] = S(0.0);
    g_row[2] = S(-r);
    g0 = S(0.0);
  }
};

}  // namespace

ModelParameters rolling_disk_defaults() {
  return {{"m", 2.0}, {"r", 0.3}, {"J", 0.09}, {"alpha", 0.5}, {"g", 9.81}};
}

std::shared_ptr<const Model> create_rolling_disk(const ModelParameters& parameters) {
  const ParameterReader p("rolling_disk", rolling_disk_defaults(), parameters);
  return make_model(RollingDisk{p.positive("m"), p.positive("r"), p.positive("J"),
                                p.get("alpha"), p.get("g")});
}

}  // namespace pcsim::mech
