// Helpers shared by the model-file tests: where the model files are, random states, comparisons
// of whole matrices, and checking an InputError's message.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/error.hpp"
#include "mech/model.hpp"
#include "modelfile/model_file.hpp"

namespace pcsim::modelfile::testing {

inline std::filesystem::path model_path(const std::string& file) {
  return std::filesystem::path(PCSIM_SOURCE_DIR) / "models" / file;
}

/// max |a - b| / max(max |b|, floor): a scale-free difference of whole matrices (the scale of
/// the largest entry, so an entry that cancels to ~0 is judged against its block's scale).
inline double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double floor = 1e-300) {
  if (a.size() == 0 && b.size() == 0) return 0.0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), floor);
}

/// The text of a model file of models/ (throws if it cannot be read).
inline std::string model_text(const std::string& file) {
  std::ifstream in(model_path(file));
  if (!in) throw std::runtime_error("cannot read models/" + file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The index of `name` in `names` (a model's coordinates, say); throws if it is absent.
inline int name_index(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::runtime_error("no '" + name + "' among the names");
  return static_cast<int>(it - names.begin());
}

/// The index of the output column `name` of a model description; throws if it has none.
inline int output_index(const ModelDescription& d, const std::string& name) {
  for (std::size_t i = 0; i < d.outputs().size(); ++i)
    if (d.outputs()[i].name == name) return static_cast<int>(i);
  throw std::runtime_error("no output '" + name + "'");
}

/// Uniform in [-1, 1].
inline double uniform(std::mt19937& rng) {
  return std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
}

/// The message of the InputError that f throws ("" if it throws none, "<other>: ..." if it
/// throws something else).
inline std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<not an InputError>: ") + e.what();
  }
  return "";
}

/// True if text contains every one of parts.
inline bool contains_all(const std::string& text, std::initializer_list<std::string> parts) {
  return std::all_of(parts.begin(), parts.end(),
                     [&](const std::string& p) { return text.find(p) != std::string::npos; });
}

/// Evaluates every quantity of a Model at one state (for comparing two models).
struct Evaluation {
  Eigen::MatrixXd M, g;
  Eigen::VectorXd h, Q, g0, gamma;
};
inline Evaluation evaluate(const mech::Model& m, const std::vector<int>& active, double t,
                           const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  Evaluation e;
  const int n = m.n(), s = static_cast<int>(active.size());
  e.M.resize(n, n);
  e.h.resize(n);
  e.Q.resize(n);
  e.g.resize(s, n);
  e.g0.resize(s);
  e.gamma.resize(s);
  m.kinetic_terms(t, q, qd, e.M, e.h);
  m.forces(t, q, qd, e.Q);
  m.constraint_rows(active, t, q, qd, e.g, e.g0, e.gamma);
  return e;
}

/// Indices of these constraint names in m (each must exist).
inline std::vector<int> indices(const mech::Model& m, const std::vector<std::string>& names) {
  std::vector<int> out;
  for (const auto& n : names) out.push_back(m.constraint_index(n));
  return out;
}

}  // namespace pcsim::modelfile::testing
