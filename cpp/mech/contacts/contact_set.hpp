// The contact set of a switching run (issue 12): the unilateral constraints among the active
// ones with their friction constraints, the segment's configuration of modes and the layout of
// rows it imposes, each contact's kinematics (gap, normal and sliding velocity) and the
// tolerances that decide them. Immutable once built; shared by the other rooms of contacts/.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/contacts/switching.hpp"
#include "mech/dynamics.hpp"
#include "mech/model.hpp"

namespace pcsim::mech::contacts {

/// Numbers in messages (9 significant digits).
std::string num(double v);

/// One unilateral contact of the run.
struct ContactDef {
  int normal = -1;    ///< constraint index of the unilateral constraint
  int friction = -1;  ///< constraint index of its active friction constraint, or -1
  /// The second friction row of a 2-D Coulomb cone (a contact that slides in a plane), or -1:
  /// rows friction and friction2 are the sliding velocity's components along two orthonormal
  /// tangent directions, and the friction force (λ_t1, λ_t2) obeys |λ_t| <= μ λ_n.
  int friction2 = -1;
  /// Constraint indices of its rough rows (ContactInfo::rough): imposed while it is closed.
  std::vector<int> rough;
  int sign = 1;       ///< gap = sign Φ, normal force = sign λ
  double e = 0.0, mu_s = 0.0, mu_k = 0.0;
  std::string name;
  bool cone() const { return friction2 >= 0; }
};

/// The contacts' modes for one segment; sigma is the sliding direction (±1) of slipping ones.
struct Config {
  std::vector<ContactMode> modes;
  std::vector<int> sigma;
  /// Per contact with a 2-D cone that slips (or empty): the unit sliding direction (v_t1, v_t2)
  /// when the segment began. The friction force follows the sliding velocity's direction
  /// within the segment; this reference only defines its event, ref·v_t through 0.
  std::vector<Eigen::Vector2d> dir;
  /// Per contact (or empty): its friction row sticks but depends on the other imposed rows
  /// (a block resting on two corners with friction has four rows on three coordinates), so it
  /// is implied, not imposed; its friction force is then carried by the others (reported 0).
  /// Bit 0: the (first) friction row, bit 1: a 2-D cone's second row.
  std::vector<char> implied;
};

/// The active set of a configuration: the constraints imposed (case order: bilateral ones,
/// closed normals and their rough rows, sticking friction rows), then the rows of sliding friction constraints
/// (not imposed: their row is the direction of the friction force and their g q̇ + g0 the
/// sliding velocity).
struct Layout {
  ActiveSet set;
  std::vector<int> imposed;       ///< constraint indices of the first s_A rows
  int s_A = 0;
  std::vector<int> normal_pos;    ///< per contact: row of its normal in set, or -1
  std::vector<int> friction_pos;  ///< per contact: row of its friction constraint, or -1
  std::vector<int> friction2_pos; ///< per contact: row of a 2-D cone's second friction row, or -1
};

/// Kinematics of one constraint row at a state.
struct Row {
  Eigen::RowVectorXd g;
  double g0 = 0.0, gamma = 0.0;
  double value(const Eigen::VectorXd& qd) const { return g.dot(qd) + g0; }
};

/// What the tolerances of a contact need of the run's options.
struct Accuracy {
  double atol = 1e-8, rtol = 1e-8;
};

class ContactSet {
 public:
  /// Builds the contacts of a run from the active constraints (indices): "" into `why`, or the
  /// reason they cannot be switched (then the set is empty).
  ContactSet(const Model& model, std::vector<int> active, Accuracy accuracy, std::string& why);

  const Model& model() const { return model_; }
  int n() const { return n_; }
  int nc() const { return static_cast<int>(contacts_.size()); }
  const ContactDef& operator[](int c) const { return contacts_[c]; }
  const std::vector<int>& active() const { return active_; }
  /// The active constraints that are neither unilateral nor friction constraints.
  const std::vector<int>& bilateral() const { return bilateral_; }
  /// Whether any contact has rough rows (without: every path is the one before them).
  bool any_rough() const { return any_rough_; }

  /// The rows a configuration imposes, then its sliding rows.
  Layout layout(const Config& cfg) const;
  /// The contact whose normal (friction) constraint is `constraint`, or -1.
  int contact_of_normal(int constraint) const;
  int contact_of_friction(int constraint) const;

  // ---- kinematics ---------------------------------------------------------------------------
  Row row(int constraint, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  /// The normal row with the gap's sign (its value is the gap rate).
  Row normal_row(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  double gap(int c, double t, const Eigen::VectorXd& q) const;
  double vn(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  double vt(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  /// Both sliding velocity components of a contact (the second 0 without a 2-D cone).
  Eigen::Vector2d vt2(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  /// The sliding speed: |v_t| (1-D), or the 2-D sliding velocity's length.
  double speed(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;

  // ---- tolerances of one contact (issue 19) ---------------------------------------------------
  //
  // Every tolerance of a contact is relative to the quantity it compares, never to the size of
  // the coordinates: a ball bouncing 50 m along the floor (x = 50, not in the gap) must bounce
  // exactly as at x = 0. The scales come from the contact's own rows:
  //  - the gap's rounding: the representation error of the coordinates (and of t) propagated
  //    through the gap function, kRound eps (sum_j |dg/dq_j| |q_j| + |dg/dt| |t|); a floor
  //    `y - 50 >= 0` with y near 50 has a rounding of 50 eps, a floor y >= 0 at x = 50 none from x;
  //  - the gap's accuracy: the integrator's absolute tolerance propagated through the gradient,
  //    10 atol sum_j |dg/dq_j|, plus the rounding;
  //  - a contact velocity's (gap rate or sliding velocity, g q_d + g0) accuracy: 10 (atol |g|_1
  //    + rtol (|g| . |q_d| + |g0|)) plus its rounding kRound eps (|g| . |q_d| + |g0|): relative to the
  //    terms that make up that velocity, so a fast slide along an incline (x_d, not in the gap
  //    rate) does not widen the normal velocity's tolerance.
  static constexpr double kEps = 2.220446049250313e-16;
  static constexpr double kRound = 100.0;
  /// A rebound whose apex is below kResolve gap roundings is an accumulation (ImpactLaw).
  static constexpr double kResolve = 16.0;
  double gap_round(int c, double t, const Eigen::VectorXd& q) const;
  double gap_tol(int c, double t, const Eigen::VectorXd& q) const;
  double velocity_tol(const Row& r, const Eigen::VectorXd& qd) const;
  double vn_tol(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  double vt_tol(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  /// The rounding of a contact velocity (the sliding function's offset).
  double velocity_round(const Row& r, const Eigen::VectorXd& qd) const;

 private:
  double row_scale(const Row& r, double t, const Eigen::VectorXd& q) const;

  const Model& model_;
  std::vector<int> active_, bilateral_;
  std::vector<ContactDef> contacts_;
  Accuracy acc_;
  int n_;
  bool any_rough_ = false;
};

/// Reactions at one state for one configuration.
struct Solved {
  Eigen::VectorXd qdd, R, lambda;     ///< lambda: the s_A imposed multipliers
  /// The multipliers of every row of the layout's set: the imposed ones, then the sliding
  /// friction rows' (the kinetic friction force −μ_k λ_n σ, or its components −μ_k λ_n v/|v| on a
  /// 2-D cone), for the per-joint reaction columns and lambda_<row> outputs.
  Eigen::VectorXd lambda_set;
  std::vector<double> lambda_n, lambda_t;  ///< per contact (0 when open / no friction)
  std::vector<double> lambda_t2;           ///< per contact: a 2-D cone's second component
  /// The friction force's magnitude |λ_t| (1-D) or |(λ_t1, λ_t2)| (2-D cone).
  double friction(int c) const { return std::hypot(lambda_t[c], lambda_t2[c]); }
};

/// Evaluates `d` at (t, q, qd) for configuration cfg (layout L) and solves for its reactions:
/// Dynamics::solve without a sliding contact, Dynamics::solve_sliding with; then each contact's
/// normal and friction force. On failure d.message() says why.
ModelIssue solve_reactions(Dynamics& d, const ContactSet& cs, const Layout& L, const Config& cfg,
                           double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                           Solved& out, ReactionMethod method);

}  // namespace pcsim::mech::contacts
