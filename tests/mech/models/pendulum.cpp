// Validation model: a planar pendulum (point mass m on a massless rod of length L) in Cartesian
// coordinates (x horizontal, y vertical up, pivot at the origin), with the holonomic constraint
// x² + y² − L² = 0. The rod tension is m(g cos φ + L φ̇²) with φ the angle from the downward
// vertical; derived quantity "tension" = −R·(x, y)/L.
#include <cmath>

#include "mech/models/registry.hpp"

namespace pcsim::mech {

namespace {

struct Pendulum {
  double m, L, grav;
  static constexpr int kCoordinates = 2;  // optional: fixed-size (faster) AD

  std::string name() const { return "pendulum"; }
  std::vector<std::string> coordinates() const { return {"x", "y"}; }
  std::vector<ConstraintInfo> constraints() const {
    return {{"length", ConstraintKind::holonomic, false}};
  }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    return m * grav * q[1];
  }
  template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const {
    return q[0] * q[0] + q[1] * q[1] - L * L;
  }
  std::vector<std::string> derived_names() const { return {"tension"}; }
  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& R, Eigen::VectorXd& out) const {
    out.resize(1);
    out[0] = -(R[0] * q[0] + R[1] * q[1]) / q.norm();
  }
};

}  // namespace

ModelParameters pendulum_defaults() { return {{"m", 1.0}, {"L", 1.0}, {"g", 9.81}}; }

std::shared_ptr<const Model> create_pendulum(const ModelParameters& parameters) {
  const ParameterReader p("pendulum", pendulum_defaults(), parameters);
  return make_model(Pendulum{p.positive("m"), p.positive("L"), p.get("g")});
}

}  // namespace pcsim::mech
