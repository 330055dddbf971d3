// The built-in models: their model files are embedded, derived at build time (the compiled tape
// as bytes) and compiled to native code; what pcsim evaluates must be what the model file says.
// Oracle: the same text loaded and derived at run time and evaluated by the tape's interpreter.
#define BOOST_TEST_MODULE sim_builtin_models
#include <boost/test/unit_test.hpp>

#include <random>
#include <string>

#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile/tape_io.hpp"
#include "sim/builtin_models.hpp"
#include "sim/file_source.hpp"

using namespace pcsim;

namespace {

std::shared_ptr<const mech::Model> instance(const modelfile::ModelDescription& d, const Eigen::VectorXd& q0) {
  return d.instantiate({}, q0, 0.0);
}

}  // namespace

// Every built-in model evaluates bit for bit as its model file derived now and interpreted:
// M, h, Q, every constraint row, g0, gamma, position residual, and the outputs, at random states.
BOOST_AUTO_TEST_CASE(built_in_models_evaluate_exactly_as_their_files) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& m : sim::embedded_models()) {
    BOOST_TEST_CONTEXT(m.file_stem) {
      const auto built = sim::embedded_description(m.file_stem);
      BOOST_TEST(!built->compiled().native.empty());  // the native path is what runs
      const auto fresh = modelfile::load_model_text(m.text, std::string(m.file_stem) + ".toml");
      BOOST_TEST(fresh->compiled().native.empty());
      const int n = built->n();
      Eigen::VectorXd q0 = Eigen::VectorXd::Zero(n);
      const auto a = instance(*built, q0), b = instance(*fresh, q0);
      std::vector<int> all;
      for (int i = 0; i < static_cast<int>(a->constraints().size()); ++i) all.push_back(i);
      for (int trial = 0; trial < 20; ++trial) {
        Eigen::VectorXd q(n), qd(n), qdd(n), R(n);
        for (int i = 0; i < n; ++i) {
          q[i] = u(rng);
          qd[i] = u(rng);
          qdd[i] = u(rng);
          R[i] = u(rng);
        }
        const double t = u(rng);
        Eigen::MatrixXd Ma(n, n), Mb(n, n), ga(all.size(), n), gb(all.size(), n);
        Eigen::VectorXd ha(n), hb(n), Qa(n), Qb(n), g0a(all.size()), g0b(all.size()),
            ca(all.size()), cb(all.size()), oa, ob;
        a->kinetic_terms(t, q, qd, Ma, ha);
        b->kinetic_terms(t, q, qd, Mb, hb);
        a->forces(t, q, qd, Qa);
        b->forces(t, q, qd, Qb);
        a->constraint_rows(all, t, q, qd, ga, g0a, ca);
        b->constraint_rows(all, t, q, qd, gb, g0b, cb);
        a->derived(t, q, qd, qdd, R, oa);
        b->derived(t, q, qd, qdd, R, ob);
        BOOST_TEST((Ma.array() == Mb.array()).all());
        BOOST_TEST((ha.array() == hb.array()).all());
        BOOST_TEST((Qa.array() == Qb.array()).all());
        BOOST_TEST((ga.array() == gb.array()).all());
        BOOST_TEST((g0a.array() == g0b.array()).all());
        BOOST_TEST((ca.array() == cb.array()).all());
        BOOST_TEST((oa.array() == ob.array() || (oa.array() != oa.array())).all());
        for (int i : all) {
          const double pa = a->position_residual(i, t, q), pb = b->position_residual(i, t, q);
          BOOST_TEST((pa == pb || (pa != pa && pb != pb)));
        }
      }
    }
  }
}

// The build-time bytes are the compiled model of the text they were made from: serializing the
// fresh derivation gives the same bytes; bytes of another text are refused (the model is then
// derived at run time, never evaluated from a stale tape).
BOOST_AUTO_TEST_CASE(build_time_tapes_match_their_texts_and_refuse_others) {
  for (const auto& m : sim::embedded_models()) {
    BOOST_TEST_CONTEXT(m.file_stem) {
      const auto& bytes = sim::embedded_model_tapes().at(m.file_stem);
      const auto fresh = modelfile::load_model_text(m.text, "x.toml");
      BOOST_TEST(modelfile::serialize_compiled(fresh->compiled(), m.text) == bytes);
      BOOST_TEST(modelfile::deserialize_compiled(bytes, m.text) != nullptr);
      BOOST_TEST(modelfile::deserialize_compiled(bytes, std::string(m.text) + " ") == nullptr);
    }
  }
}
