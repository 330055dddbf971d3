// The built-in model table, the model-file loader hooks, and the built-in models of the C++
// model registry (pendulum, rolling_disk, slider_crank) as model sources.
#include "sim/model_source.hpp"

#include <mutex>

#include "common/error.hpp"
#include "mech/models/registry.hpp"

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
  FileModelLoader file_loader;
  InlineModelLoader inline_loader;
};

Builtins& builtins() {
  static Builtins b;
  return b;
}

/// A model of the C++ registry (cpp/mech/models): its coordinates, constraints and derived
/// names come from the model itself, its parameters from the registry's defaults (the factory
/// checks the ranges and names the parameter).
class RegistrySource final : public ModelSource {
 public:
  explicit RegistrySource(std::string name) : name_(std::move(name)) {
    const mech::ModelParameters defaults = mech::default_parameters(name_);
    for (const auto& [k, v] : defaults) {
      ParameterSpec p;
      p.name = k;
      p.value = v;
      parameters_.push_back(p);
    }
    const auto model = mech::create_model(name_, {});
    coordinates_ = model->coordinates();
    for (const auto& c : model->constraints())
      constraints_.push_back({c.name, c.kind, c.active_by_default, ""});
    outputs_ = model->derived_names();
  }
  const std::string& name() const override { return name_; }
  std::string origin() const override { return "built-in model '" + name_ + "'"; }
  const std::vector<std::string>& coordinates() const override { return coordinates_; }
  const std::vector<ParameterSpec>& parameters() const override { return parameters_; }
  const std::vector<ConstraintOffer>& constraints() const override { return constraints_; }
  const std::vector<std::string>& outputs() const override { return outputs_; }
  double period(const ParameterValues&) const override {
    return std::numeric_limits<double>::quiet_NaN();
  }
  std::shared_ptr<const mech::Model> instantiate(const ParameterValues& parameters,
                                                 const Eigen::VectorXd&, double,
                                                 const toml::table&,
                                                 const std::string&) const override {
    return mech::create_model(name_, parameters);
  }

 private:
  std::string name_;
  std::vector<std::string> coordinates_, outputs_;
  std::vector<ParameterSpec> parameters_;
  std::vector<ConstraintOffer> constraints_;
};

void register_registry_models(Builtins& b) {
  static bool done = false;  // under b.mutex
  if (done) return;
  done = true;
  for (const std::string& name : mech::model_names()) {
    if (b.factories.count(name)) continue;
    b.factories[name] = [name] { return std::make_shared<const RegistrySource>(name); };
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
    register_registry_models(b);
    if (auto it = b.built.find(name); it != b.built.end()) return it->second;
    auto it = b.factories.find(name);
    if (it == b.factories.end()) return nullptr;
    factory = it->second;
  }
  auto source = factory();
  std::lock_guard<std::mutex> lock(b.mutex);
  return b.built.emplace(name, std::move(source)).first->second;
}

std::vector<std::string> builtin_names() {
  Builtins& b = builtins();
  std::lock_guard<std::mutex> lock(b.mutex);
  register_registry_models(b);
  std::vector<std::string> names;
  for (const auto& [k, v] : b.factories) names.push_back(k);
  return names;
}

void set_model_file_loaders(FileModelLoader file, InlineModelLoader inline_table) {
  Builtins& b = builtins();
  std::lock_guard<std::mutex> lock(b.mutex);
  b.file_loader = std::move(file);
  b.inline_loader = std::move(inline_table);
}

std::shared_ptr<const ModelSource> load_model_file(const std::filesystem::path& file) {
  FileModelLoader loader;
  {
    Builtins& b = builtins();
    std::lock_guard<std::mutex> lock(b.mutex);
    loader = b.file_loader;
  }
  if (!loader) throw InputError(file.string() + ": model files are not available in this build");
  return loader(file);
}

std::shared_ptr<const ModelSource> load_inline_model(const toml::table& model,
                                                     const std::filesystem::path& case_file) {
  InlineModelLoader loader;
  {
    Builtins& b = builtins();
    std::lock_guard<std::mutex> lock(b.mutex);
    loader = b.inline_loader;
  }
  if (!loader)
    throw InputError(case_file.string() + ": key 'model': inline [model] tables are not available "
                                          "in this build");
  return loader(model, case_file);
}

}  // namespace pcsim::sim
