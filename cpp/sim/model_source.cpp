// The built-in model table: the sieve (registered by its component) and the embedded model
// files of the engine's example systems (pendulum, rolling_disk, slider_crank).
#include "sim/model_source.hpp"

#include <mutex>

#include "common/error.hpp"
#include "sim/file_source.hpp"

namespace pcsim::sim {

int ModelSource::coordinate_index(const std::string& coordinate) const {
  const auto& c = coordinates();
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c[i] == coordinate) return static_cast<int>(i);
  return -1;
}

std::shared_ptr<const ModelSource> ModelSource::with_added_constraints(
    const std::vector<AddedConstraint>& added, const std::string& where) const {
  throw InputError(where + ": key 'constraints.added." + added.front().name + "': the " +
                   origin() +
                   " cannot take added constraints (only models from model files can); write "
                   "the model as a model file to add constraints");
}

namespace {

struct Builtins {
  std::mutex mutex;
  std::map<std::string, SourceFactory> factories;
  std::map<std::string, std::shared_ptr<const ModelSource>> built;
  std::string default_name;  ///< the model of a case without `model` ("" = none)
};

Builtins& builtins() {
  static Builtins b;
  return b;
}

void register_embedded_models(Builtins& b) {
  static bool done = false;  // under b.mutex
  if (done) return;
  done = true;
  // The built-in model files: the engine's example systems by their names (the sieve is
  // registered by its own application, with its client).
  for (const char* name : {"pendulum", "rolling_disk", "slider_crank"}) {
    if (b.factories.count(name)) continue;
    const std::string n = name;
    b.factories[n] = [n] { return make_embedded_model_source(n, n); };
  }
}

}  // namespace

void register_builtin(const std::string& name, SourceFactory factory) {
  Builtins& b = builtins();
  std::lock_guard<std::mutex> lock(b.mutex);
  b.factories[name] = std::move(factory);
  b.built.erase(name);
}

std::shared_ptr<const ModelSource> find_builtin(const std::string& name) {
  Builtins& b = builtins();
  SourceFactory factory;
  {
    std::lock_guard<std::mutex> lock(b.mutex);
    register_embedded_models(b);
    if (auto it = b.built.find(name); it != b.built.end()) return it->second;
    auto it = b.factories.find(name);
    if (it == b.factories.end()) return nullptr;
    factory = it->second;
  }
  auto source = factory();
  std::lock_guard<std::mutex> lock(b.mutex);
  return b.built.emplace(name, std::move(source)).first->second;
}

void set_default_builtin(const std::string& name) {
  Builtins& b = builtins();
  std::lock_guard<std::mutex> lock(b.mutex);
  b.default_name = name;
}

std::shared_ptr<const ModelSource> default_builtin() {
  std::string name;
  {
    Builtins& b = builtins();
    std::lock_guard<std::mutex> lock(b.mutex);
    name = b.default_name;
  }
  return name.empty() ? nullptr : find_builtin(name);
}

std::vector<std::string> builtin_names() {
  Builtins& b = builtins();
  std::lock_guard<std::mutex> lock(b.mutex);
  register_embedded_models(b);
  std::vector<std::string> names;
  for (const auto& [k, v] : b.factories) names.push_back(k);
  return names;
}

}  // namespace pcsim::sim
