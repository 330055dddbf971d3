#include "sim/file_source.hpp"

#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"
#include "sim/builtin_models.hpp"

namespace pcsim::sim {

ParameterSpec parameter_spec(const modelfile::ParameterSpec& p) {
  ParameterSpec s;
  s.name = p.name;
  s.value = p.value;
  s.unit = p.unit;
  s.meaning = p.meaning;
  s.min = p.min;
  s.max = p.max;
  s.min_exclusive = p.min_exclusive;
  s.max_exclusive = p.max_exclusive;
  return s;
}

namespace {

/// 64-bit FNV-1a of a text, as 16 hex digits (the fingerprint of a model's definition).
std::string fnv1a(const std::string& text) {
  unsigned long long h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", h);
  return buf;
}

class FileModelSource final : public ModelSource {
 public:
  FileModelSource(std::shared_ptr<const modelfile::ModelDescription> d, std::string origin,
                  std::string fingerprint, std::string text)
      : d_(std::move(d)), origin_(std::move(origin)), fingerprint_(std::move(fingerprint)),
        text_(std::move(text)) {
    for (const auto& p : d_->parameters()) parameters_.push_back(parameter_spec(p));
    for (const auto& c : d_->constraints())
      constraints_.push_back({c.name, c.kind, c.active_by_default, "", c.unilateral, c.friction, c.rough});
    for (const auto& o : d_->outputs()) outputs_.push_back(o.name);
  }

  const std::string& name() const override { return d_->name(); }
  std::string origin() const override { return origin_; }
  std::string fingerprint() const override { return fingerprint_; }
  const std::vector<std::string>& coordinates() const override { return d_->coordinates(); }
  const std::vector<ParameterSpec>& parameters() const override { return parameters_; }
  const std::vector<ConstraintOffer>& constraints() const override { return constraints_; }
  const std::vector<std::string>& outputs() const override { return outputs_; }
  double period(const ParameterValues& p) const override { return d_->period(p); }
  std::vector<std::string> slow_coordinates() const override { return d_->slow_coordinates(); }
  std::vector<EulerBody> euler_bodies() const override {
    std::vector<EulerBody> out;
    for (const auto& b : d_->euler_bodies()) out.push_back({b.name, b.e, b.joint});
    return out;
  }
  std::string definition_text() const override { return text_; }

  std::shared_ptr<const ModelSource> with_added_constraints(
      const std::vector<AddedConstraint>& added, const std::string& where) const override {
    std::vector<modelfile::ExtraConstraint> extra;
    std::string key_text;
    for (const auto& a : added) {
      modelfile::ExtraConstraint e;
      e.name = a.name;
      e.holonomic = a.holonomic;
      e.origin = where;
      e.key = "constraints.added." + a.name;
      extra.push_back(e);
      key_text += "\n[added] " + a.name + " = " + a.holonomic;
    }
    return std::make_shared<const FileModelSource>(d_->with_constraints(extra), origin_,
                                                   fnv1a(fingerprint_ + key_text), text_);
  }

  std::shared_ptr<const mech::Model> instantiate(const ParameterValues& parameters,
                                                 const Eigen::VectorXd& q0, double t0,
                                                 const toml::table&,
                                                 const std::string& variant) const override {
    if (!variant.empty())
      throw InputError("the " + origin_ + " has no variant '" + variant + "'");
    return d_->instantiate(parameters, q0, t0);
  }

  const std::shared_ptr<const modelfile::ModelDescription>& description() const { return d_; }

 private:
  std::shared_ptr<const modelfile::ModelDescription> d_;
  std::string origin_, fingerprint_, text_;
  std::vector<ParameterSpec> parameters_;
  std::vector<ConstraintOffer> constraints_;
  std::vector<std::string> outputs_;
};

}  // namespace

std::shared_ptr<const ModelSource> make_file_model_source(
    std::shared_ptr<const modelfile::ModelDescription> description, std::string origin,
    const std::string& text) {
  return std::make_shared<const FileModelSource>(std::move(description), std::move(origin),
                                                 fnv1a(text), text);
}

const char* embedded_model_text(const std::string& file_stem) {
  for (const auto& m : embedded_models())
    if (file_stem == m.file_stem) return m.text;
  throw std::out_of_range("no embedded model file '" + file_stem + "'");
}

std::shared_ptr<const modelfile::ModelDescription> embedded_description(const std::string& file_stem) {
  static std::mutex m;
  static std::map<std::string, std::shared_ptr<const modelfile::ModelDescription>> cache;
  std::lock_guard<std::mutex> lock(m);
  auto& d = cache[file_stem];
  if (!d) {
    // The compiled model made at build time, when it matches the text (it always does in a
    // consistent build; otherwise the model is derived here as any model file is).
    const auto& tapes = embedded_model_tapes();
    const auto it = tapes.find(file_stem);
    const auto& natives = embedded_model_natives();
    const auto nt = natives.find(file_stem);
    d = modelfile::load_model_text(embedded_model_text(file_stem),
                                   "built-in models/" + file_stem + ".toml",
                                   it == tapes.end() ? nullptr : &it->second,
                                   nt == natives.end() ? nullptr : &nt->second);
  }
  return d;
}

std::shared_ptr<const ModelSource> make_embedded_model_source(const std::string& name,
                                                              const std::string& file_stem) {
  return make_file_model_source(embedded_description(file_stem), "built-in model '" + name + "'",
                                embedded_model_text(file_stem));
}

std::shared_ptr<const ModelSource> load_model_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  auto d = modelfile::load_model_text(text.str(), file);
  return make_file_model_source(std::move(d), "model file " + file.string(), text.str());
}

std::shared_ptr<const ModelSource> load_inline_model(const toml::table& model,
                                                     const std::filesystem::path& case_file) {
  std::ostringstream text;
  text << model;
  auto d = modelfile::parse_model_table(model, case_file, "model");
  // The same table as a model file of its own (model.toml of a run): [model] around it.
  toml::table file;
  file.insert("model", model);
  std::ostringstream as_file;
  as_file << file << "\n";
  return std::make_shared<const FileModelSource>(std::move(d), "model of " + case_file.string(),
                                                 fnv1a(text.str()), as_file.str());
}

}  // namespace pcsim::sim
