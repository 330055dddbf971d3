#include "mech/models/registry.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "common/error.hpp"

// ---- The list of built-in models: one line X(<name>) per model -------------------------------
// Each tests/mech/models/<name>.cpp defines create_<name>(const ModelParameters&) and
// <name>_defaults().
#define PCSIM_MECH_MODELS(X) \
  X(pendulum)                \
  X(rolling_disk)            \
  X(slider_crank)

namespace pcsim::mech {

#define PCSIM_DECLARE(name)                                                    \
  std::shared_ptr<const Model> create_##name(const ModelParameters& parameters); \
  ModelParameters name##_defaults();
PCSIM_MECH_MODELS(PCSIM_DECLARE)
#undef PCSIM_DECLARE

namespace {

struct Entry {
  ModelFactory factory;
  ModelParameters defaults;
};

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> r = [] {
    std::map<std::string, Entry> init;
#define PCSIM_ENTRY(name) init[#name] = Entry{&create_##name, name##_defaults()};
    PCSIM_MECH_MODELS(PCSIM_ENTRY)
#undef PCSIM_ENTRY
    return init;
  }();
  return r;
}

}  // namespace

std::shared_ptr<const Model> create_model(const std::string& name,
                                          const ModelParameters& parameters) {
  ModelFactory factory;
  {
    std::lock_guard<std::mutex> lock(registry_mutex());
    auto it = registry().find(name);
    if (it == registry().end()) {
      std::string known;
      for (const auto& [k, v] : registry()) known += (known.empty() ? "" : ", ") + k;
      throw InputError("unknown model '" + name + "' (known models: " + known + ")");
    }
    factory = it->second.factory;
  }
  return factory(parameters);
}

std::vector<std::string> model_names() {
  std::lock_guard<std::mutex> lock(registry_mutex());
  std::vector<std::string> names;
  for (const auto& [k, v] : registry()) names.push_back(k);
  return names;
}

ModelParameters default_parameters(const std::string& name) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  auto it = registry().find(name);
  if (it == registry().end()) throw InputError("unknown model '" + name + "'");
  return it->second.defaults;
}

void register_model(const std::string& name, ModelFactory factory, ModelParameters defaults) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  registry()[name] = Entry{std::move(factory), std::move(defaults)};
}

ParameterReader::ParameterReader(std::string model, ModelParameters defaults,
                                 const ModelParameters& given)
    : model_(std::move(model)), values_(std::move(defaults)) {
  for (const auto& [key, value] : given) {
    auto it = values_.find(key);
    if (it == values_.end()) {
      std::string known;
      for (const auto& [k, v] : values_) known += (known.empty() ? "" : ", ") + k;
      throw InputError("model '" + model_ + "': unknown parameter '" + key +
                       "' (expected one of: " + known + ")");
    }
    if (!std::isfinite(value)) {
      throw InputError("model '" + model_ + "': parameter '" + key + "' must be a finite number");
    }
    it->second = value;
  }
}

double ParameterReader::get(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) {
    throw InputError("model '" + model_ + "': no parameter '" + key + "'");
  }
  return it->second;
}

double ParameterReader::positive(const std::string& key) const {
  const double v = get(key);
  if (!(v > 0.0)) {
    throw InputError("model '" + model_ + "': parameter '" + key + "' must be > 0, got " +
                     std::to_string(v));
  }
  return v;
}

}  // namespace pcsim::mech
