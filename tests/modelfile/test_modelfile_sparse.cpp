// The sparse structured compatibility solve (issue 23, mech/sparse_compat.hpp) against the dense
// one: for every model file in models/ (and models/contact/), at random states (also with the
// coordinates shifted far from the origin, Euler parameters excepted), with every constraint
// active, the reactions R and accelerations q̈ of the two paths agree to 1e-12 of their scale,
// and they hand over to the
// rank-revealing solve at the same states; the sparse minimum-norm projection agrees with
// Huang's on the 30-link chain. The oracle is the dense path (an independent formulation: dense
// Cholesky of M and of g M⁻¹ gᵀ in natural order vs block inverses, sparse products and an AMD-
// ordered LDLT), which test_reactions checks against the paper's [G; Dᵀ] solve.
#define BOOST_TEST_MODULE modelfile_sparse
#include <boost/test/unit_test.hpp>
#include "common/eigen_instances.hpp"

#include <algorithm>

#include "common/eigen_instances.hpp"

#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>

#include "mech/dynamics.hpp"
#include "mech/projection.hpp"
#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"
#include "chain_model.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

std::vector<std::filesystem::path> model_files() {
  std::vector<std::filesystem::path> out;
  for (const char* dir : {"", "contact"}) {
    const auto d = std::filesystem::path(PCSIM_SOURCE_DIR) / "models" / dir;
    for (const auto& e : std::filesystem::directory_iterator(d))
      if (e.path().extension() == ".toml") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(sparse_and_dense_structured_solves_agree_on_every_model) {
  int compared = 0, sparse_solved = 0;
  for (const auto& file : model_files()) {
    BOOST_TEST_CONTEXT(file.filename().string()) {
      // Each model's states from its own stream (seeded by its file name, FNV-1a): with one stream
      // for all, adding a model to models/ moved every later model's random states, and a state
      // near a rank hand-over (bricard_a04's) could move past the test's tolerance.
      std::uint32_t seed = 2166136261u;
      for (const unsigned char c : file.filename().string()) seed = (seed ^ c) * 16777619u;
      std::mt19937 rng(seed);
      const auto desc = load_model_file(file);
      const int n0 = static_cast<int>(desc->coordinates().size());
      Eigen::VectorXd q0(n0);  // fixes the constants of from_initial constraints
      for (int i = 0; i < n0; ++i) q0[i] = uniform(rng);
      const auto model = desc->instantiate({}, q0);
      const int n = model->n(), s = static_cast<int>(model->constraints().size());
      std::vector<int> all(s);
      for (int i = 0; i < s; ++i) all[i] = i;
      const mech::ActiveSet set = mech::ActiveSet::of(*model, all);
      mech::Dynamics dense(*model, Kernel::cpp), sparse(*model, Kernel::cpp);
      dense.sparse_min_n = INT_MAX;
      sparse.sparse_min_n = 0;
      sparse.sparse_evaluation = true;  // M and g from the model's sparse values (issue 23)
      // Euler parameters are not positions: shifted by 1e3 they put |e|² at 4e6 and M's entries
      // at ~1e20, where rounding leaves M indefinite (the engine mount's block, its centre of mass
      // off its frame's origin: eigenvalues -1.5e4 ... 2.6e20) and neither solve means anything.
      std::vector<bool> euler(static_cast<std::size_t>(n), false);
      for (const auto& b : desc->euler_bodies())
        for (const auto& c : b.e)
          for (int i = 0; i < n; ++i)
            if (model->coordinates()[static_cast<std::size_t>(i)] == c) euler[static_cast<std::size_t>(i)] = true;
      for (int k = 0; k < 8; ++k) {
        const double shift = k % 2 ? 1e3 : 0.0;  // far from the origin on odd states
        Eigen::VectorXd q(n), qd(n);
        for (int i = 0; i < n; ++i) {
          q[i] = (euler[static_cast<std::size_t>(i)] ? 0.0 : shift) + uniform(rng);
          qd[i] = uniform(rng);
        }
        const double t = 0.5 * (1.0 + uniform(rng));
        const auto e1 = dense.evaluate(set, t, q, qd);
        const auto e2 = sparse.evaluate(set, t, q, qd);
        BOOST_TEST(static_cast<int>(e1) == static_cast<int>(e2));
        BOOST_TEST(sparse.sparse_evaluated());
        if (e1 != mech::ModelIssue::none) continue;
        const auto r1 = dense.solve(mech::ReactionMethod::compatibility_structured);
        const auto r2 = sparse.solve(mech::ReactionMethod::compatibility_structured);
        BOOST_TEST(static_cast<int>(r1) == static_cast<int>(r2));
        BOOST_TEST(!dense.used_sparse);
        if (r1 != mech::ModelIssue::none) continue;
        // The hand-over to the rank-revealing solve is decided from the Cholesky pivots, which
        // the sparse factor takes in its own (fill-reducing) order: at a state near the
        // threshold (a row within about 1e-2 rad of dependence) one path may hand over and the
        // other not. There the filter changes the solution by (mu/sigma)^4 relative, mu =
        // 1e-6 sigma_max: agreement to 1e-8 at the threshold (below). Both rank-revealing: the same filtered SVD of two
        // equivalent factorizations, agreement to 1e-10 (the issue's figure for unique R);
        // both full rank: 1e-12.
        // Full rank, the tolerance grows with the conditioning of g M^-1 g^T (rows scaled to
        // unit norm): at random states a redundant mechanism (the parallelogram with a third
        // crank) is full rank but nearly dependent, and the two factorizations round apart by
        // about kappa u.
        double kappa = 1;
        if (s > 0 && !dense.rank_revealing) {
          Eigen::MatrixXd gs = dense.g;
          for (int r = 0; r < gs.rows(); ++r) gs.row(r) /= gs.row(r).norm();
          const Eigen::MatrixXd S = gs * dense.M.llt().solve(gs.transpose());
          Eigen::JacobiSVD<Eigen::MatrixXd> svd(S);
          kappa = svd.singularValues()(0) / svd.singularValues()(svd.singularValues().size() - 1);
        }
        // One path handed over, the other not: the filtered solution differs from the exact one
        // by (mu/sigma_min)^4 relative along the weakest direction (Dynamics::kFilter, mu =
        // 1e-6 sigma_max), sigma_min the smallest singular value of the row-scaled L^-1 g^T at
        // this state. The pivot test runs in each factor's own order, so sigma_min may lie well
        // below the threshold's 1e-2: bricard_a04 at a random state (off its constraints) has
        // sigma_min = 8.3e-5 sigma_max, and the two paths differ by 2.096e-8 = (1e-6/8.3e-5)^4.
        double mixed_tol = 1e-8;
        if (dense.rank_revealing != sparse.rank_revealing) {
          Eigen::MatrixXd gs = dense.g;
          for (int r = 0; r < gs.rows(); ++r) gs.row(r) /= gs.row(r).norm();
          const Eigen::MatrixXd B = dense.M.llt().matrixL().solve(gs.transpose());
          const Eigen::JacobiSVD<Eigen::MatrixXd> sv(B);
          const auto& v = sv.singularValues();
          const double ratio = v[v.size() - 1] / v[0];
          mixed_tol = std::max(1e-8, 2.0 * std::pow(mech::Dynamics::kFilter / ratio, 4));
        }
        const double tol = dense.rank_revealing != sparse.rank_revealing ? mixed_tol
                           : dense.rank_revealing                        ? 1e-10
                                                                         : std::max(1e-12, 10 * 0x1p-53 * kappa);
        ++compared;
        if (sparse.used_sparse && !sparse.rank_revealing) ++sparse_solved;
        BOOST_TEST(rel_diff(sparse.R, dense.R, 1e-300) <= tol);
        // q̈ = M⁻¹(Q − h + R): where the reaction nearly cancels the applied forces, q̈ is small
        // against M⁻¹R and inherits R's rounding; its difference is measured against both.
        const double qdd_scale = dense.qdd.norm() + dense.M.llt().solve(dense.R).norm();
        BOOST_TEST((sparse.qdd - dense.qdd).norm() <= tol * qdd_scale, "kappa " << kappa);
        if (dense.rank_revealing != sparse.rank_revealing) continue;
        if (s > 0 && !dense.rank_revealing) BOOST_TEST(rel_diff(sparse.lambda, dense.lambda) <= tol, "kappa " << kappa);
      }
    }
  }
  // The comparison ran, and mostly on the sparse path itself (not only through hand-overs).
  BOOST_TEST(compared >= 50);
  BOOST_TEST(sparse_solved >= 40);
}

BOOST_AUTO_TEST_CASE(sparse_projection_agrees_with_huang_on_the_chain) {
  const auto desc = load_model_file(model_path("pendulum_chain_30.toml"));
  const auto model = desc->instantiate({});
  const int n = model->n(), s = static_cast<int>(model->constraints().size());
  std::vector<int> all(s);
  for (int i = 0; i < s; ++i) all[i] = i;
  std::mt19937 rng(5);
  // A bent chain, then disturbed off the constraints (positions and velocities).
  Eigen::VectorXd q(n), qd(n);
  double px = 0, py = 0;
  for (int i = 0; i < n / 3; ++i) {
    const double th = 0.7 * std::sin(0.4 * i) + 0.2, h = 0.05;
    q.segment(3 * i, 3) << px + h * std::sin(th), py - h * std::cos(th), th;
    px += 2 * h * std::sin(th);
    py -= 2 * h * std::cos(th);
  }
  for (int i = 0; i < n; ++i) {
    q[i] += 1e-4 * uniform(rng);
    qd[i] = uniform(rng);
  }
  Eigen::VectorXd q1 = q, qd1 = qd, q2 = q, qd2 = qd;
  mech::ProjectionWork w1, w2;
  w1.sparse_min_n = INT_MAX;
  w2.sparse_min_n = 0;
  double dq1, dv1, dq2, dv2;
  std::string m1, m2;
  BOOST_TEST(static_cast<int>(mech::project_state(*model, all, 0.0, q1, qd1, Kernel::cpp, 1e-12,
                                                  dq1, dv1, m1, w1)) == 0);
  BOOST_TEST(static_cast<int>(mech::project_state(*model, all, 0.0, q2, qd2, Kernel::cpp, 1e-12,
                                                  dq2, dv2, m2, w2)) == 0);
  BOOST_TEST(dq1 > 1e-5);  // the projection did move the state
  BOOST_TEST((q1 - q2).cwiseAbs().maxCoeff() <= 1e-12);
  BOOST_TEST((qd1 - qd2).cwiseAbs().maxCoeff() <= 1e-12 * qd1.cwiseAbs().maxCoeff());
}

BOOST_AUTO_TEST_CASE(sparse_path_is_the_default_for_large_models_and_analyses_once) {
  // The 30-link chain (n = 90 >= kSparseMinN) takes the sparse path by default; the pattern is
  // fixed, so repeated solves at other states do not analyse it again.
  const auto desc = load_model_file(model_path("pendulum_chain_30.toml"));
  const auto model = desc->instantiate({});
  const int n = model->n(), s = static_cast<int>(model->constraints().size());
  BOOST_TEST(n >= mech::Dynamics::kSparseMinN);
  std::vector<int> all(s);
  for (int i = 0; i < s; ++i) all[i] = i;
  const mech::ActiveSet set = mech::ActiveSet::of(*model, all);
  mech::Dynamics dyn(*model, Kernel::cpp);
  std::mt19937 rng(7);
  for (int k = 0; k < 5; ++k) {
    Eigen::VectorXd q(n), qd(n);
    for (int i = 0; i < n; ++i) {
      q[i] = uniform(rng);
      qd[i] = uniform(rng);
    }
    BOOST_TEST(static_cast<int>(dyn.evaluate(set, 0.0, q, qd)) == 0);
    BOOST_TEST(static_cast<int>(dyn.solve(mech::ReactionMethod::compatibility_structured)) == 0);
    BOOST_TEST(dyn.used_sparse);
  }
  BOOST_TEST(dyn.sparse_solver().analyses_M() == 1);
  BOOST_TEST(dyn.sparse_solver().analyses_S() == 1);
}

namespace {

// The same model without its sparse structure (the dense interface only): the oracle of the
// runs below, every evaluation dense as before issue 23's sparse interface.
class DenseOnly final : public mech::Model {
 public:
  explicit DenseOnly(std::shared_ptr<const mech::Model> m) : m_(std::move(m)) {
    name_ = m_->name();
    coordinates_ = m_->coordinates();
    constraints_ = m_->constraints();
    derived_names_ = m_->derived_names();
  }
  void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& M, Eigen::VectorXd& h) const override {
    m_->kinetic_terms(t, q, qd, M, h);
  }
  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override {
    m_->forces(t, q, qd, Q);
  }
  void constraint_rows(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& qd, Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                       Eigen::VectorXd& gamma) const override {
    m_->constraint_rows(active, t, q, qd, g, g0, gamma);
  }
  double position_residual(int i, double t, const Eigen::VectorXd& q) const override {
    return m_->position_residual(i, t, q);
  }
  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
               Eigen::VectorXd& out) const override {
    m_->derived(t, q, qd, qdd, R, out);
  }

 private:
  std::shared_ptr<const mech::Model> m_;
};

std::shared_ptr<const mech::Model> chain_model(int N) {
  const std::string text = pendulum_chain_toml(N);
  const toml::table doc = toml::parse(text);
  return parse_model_table(*doc["model"].as_table(), "chain.toml")->instantiate({});
}

}  // namespace

BOOST_AUTO_TEST_CASE(sparse_model_values_agree_with_the_dense_model_on_large_models) {
  // The chains of 20 and 40 links (n = 60, 120) and every model in models/ with n >= 60, at
  // random states (odd ones far from the origin), with and without Baumgarte terms: the model's
  // sparse values give exactly its dense M and g (densify), and the sparse path fed by them
  // (Dynamics::sparse_evaluation, default threshold) gives R, lambda and q̈ within 1e-12 of the
  // dense structured solve (relative: a different elimination order, rounding only; the
  // chain's g M^-1 g^T is well conditioned).
  std::vector<std::pair<std::string, std::shared_ptr<const mech::Model>>> models = {
      {"chain 20", chain_model(20)}, {"chain 40", chain_model(40)}};
  for (const auto& file : model_files()) {
    const auto desc = load_model_file(file);
    if (static_cast<int>(desc->coordinates().size()) < mech::Dynamics::kSparseMinN) continue;
    models.emplace_back(file.filename().string(), desc->instantiate({}));
  }
  BOOST_TEST(models.size() >= 3u);  // pendulum_chain_30 at least
  std::mt19937 rng(2323);
  int solved = 0;
  for (const auto& [name, model] : models) {
    BOOST_TEST_CONTEXT(name) {
      BOOST_TEST(model->has_sparse_structure());
      const int n = model->n(), s = static_cast<int>(model->constraints().size());
      std::vector<int> all(s);
      for (int i = 0; i < s; ++i) all[i] = i;
      const mech::ActiveSet set = mech::ActiveSet::of(*model, all);
      for (const auto stab : {mech::Stabilization::none, mech::Stabilization::baumgarte}) {
        mech::Dynamics dense(*model, Kernel::cpp, stab, 5.0, 7.0);
        mech::Dynamics sparse(*model, Kernel::cpp, stab, 5.0, 7.0);
        dense.sparse_min_n = INT_MAX;
        sparse.sparse_evaluation = true;
        for (int k = 0; k < 4; ++k) {
          const double shift = k % 2 ? 1e3 : 0.0;
          Eigen::VectorXd q(n), qd(n);
          for (int i = 0; i < n; ++i) {
            q[i] = shift + uniform(rng);
            qd[i] = uniform(rng);
          }
          BOOST_TEST(static_cast<int>(dense.evaluate(set, 0.3, q, qd)) == 0);
          BOOST_TEST(static_cast<int>(sparse.evaluate(set, 0.3, q, qd)) == 0);
          BOOST_TEST(sparse.sparse_evaluated());
          BOOST_TEST(rel_diff(sparse.gamma, dense.gamma) <= 1e-14);
          BOOST_TEST(static_cast<int>(dense.solve(mech::ReactionMethod::compatibility_structured)) == 0);
          BOOST_TEST(static_cast<int>(sparse.solve(mech::ReactionMethod::compatibility_structured)) == 0);
          BOOST_TEST(sparse.used_sparse);
          BOOST_TEST(!sparse.rank_revealing);
          BOOST_TEST(!dense.rank_revealing);
          BOOST_TEST(sparse.velocity_residual(qd) == dense.velocity_residual(qd));
          BOOST_TEST(rel_diff(sparse.R, dense.R) <= 1e-12);
          BOOST_TEST(rel_diff(sparse.lambda, dense.lambda) <= 1e-12);
          BOOST_TEST(rel_diff(sparse.qdd, dense.qdd) <= 1e-12);
          ++solved;
          // The dense matrices filled from the sparse values are the model's, exactly.
          sparse.densify();
          BOOST_TEST((sparse.M.array() == dense.M.array()).all());
          BOOST_TEST((sparse.g.array() == dense.g.array()).all());
        }
      }
    }
  }
  BOOST_TEST(solved >= 24);
}

BOOST_AUTO_TEST_CASE(a_run_on_sparse_values_follows_the_dense_run) {
  // mech::simulate takes the sparse values for a model with the structure (n >= 60); the same
  // chain without its structure runs dense throughout. 0.05 s of motion of a 20-link chain
  // (drift projection on): the end states agree to the integrator's tolerance (the two runs
  // round differently, so step sizes may differ in their last bits).
  const auto sparse_model = chain_model(20);
  const DenseOnly dense_model(sparse_model);
  BOOST_TEST(!dense_model.has_sparse_structure());
  const int n = sparse_model->n();
  Eigen::VectorXd q0(n), qd0 = Eigen::VectorXd::Zero(n);
  const double a = 0.5, h = 0.05;
  for (int i = 0; i < n / 3; ++i)
    q0.segment(3 * i, 3) << (2 * i + 1) * h * std::sin(a), -(2 * i + 1) * h * std::cos(a), a;
  mech::SimulationOptions o;
  o.kernel = Kernel::cpp;
  o.method = OdeMethod::automatic;
  o.t_end = 0.05;
  o.rtol = o.atol = 1e-10;
  const auto r1 = mech::simulate(*sparse_model, q0, qd0, o);
  const auto r2 = mech::simulate(dense_model, q0, qd0, o);
  BOOST_TEST(static_cast<int>(r1.status) == static_cast<int>(mech::SimulationStatus::success));
  BOOST_TEST(static_cast<int>(r2.status) == static_cast<int>(mech::SimulationStatus::success));
  BOOST_TEST((r1.q_end - q0).norm() > 1e-3);  // it moved
  BOOST_TEST((r1.q_end - r2.q_end).cwiseAbs().maxCoeff() <= 1e-9);
  BOOST_TEST((r1.qd_end - r2.qd_end).cwiseAbs().maxCoeff() <= 1e-8);
  BOOST_TEST(r1.residual_pos_max <= 1e-9);
  BOOST_TEST(std::abs(r1.residual_vel_max - r2.residual_vel_max) <= 1e-9);
}
