// The built-in sieve with its C++ variants (variants.hpp): the shipped source, forwarded, plus
// the C++ forms of model.hpp for RunOptions::variant.
#include "sieve/support/variants.hpp"

#include <mutex>

#include "common/error.hpp"
#include "sieve/source.hpp"
#include "sieve/support/model.hpp"
#include "sieve/support/settings.hpp"
#include "sim/model_source.hpp"

namespace pcsim::sieve::testing {

namespace {

class VariantSource final : public sim::ModelSource {
 public:
  explicit VariantSource(std::shared_ptr<const sim::ModelSource> shipped)
      : shipped_(std::move(shipped)) {}
  const std::string& name() const override { return shipped_->name(); }
  std::string origin() const override { return shipped_->origin(); }
  const std::vector<std::string>& coordinates() const override { return shipped_->coordinates(); }
  const std::vector<sim::ParameterSpec>& parameters() const override {
    return shipped_->parameters();
  }
  const std::vector<sim::ConstraintOffer>& constraints() const override {
    return shipped_->constraints();
  }
  const std::vector<std::string>& outputs() const override { return shipped_->outputs(); }
  std::string fingerprint() const override { return shipped_->fingerprint(); }
  double period(const sim::ParameterValues& p) const override { return shipped_->period(p); }
  std::vector<std::string> slow_coordinates() const override {
    return shipped_->slow_coordinates();
  }
  std::shared_ptr<const sim::ModelSource> with_added_constraints(
      const std::vector<sim::AddedConstraint>& added, const std::string& where) const override {
    return shipped_->with_added_constraints(added, where);
  }
  std::shared_ptr<const mech::Model> instantiate(const sim::ParameterValues& parameters,
                                                 const Eigen::VectorXd& q0, double t0,
                                                 const toml::table& case_table,
                                                 const std::string& variant) const override {
    if (variant.empty() || variant == "model_file")
      return shipped_->instantiate(parameters, q0, t0, case_table, variant);
    const auto tr = parameters.find("t_runup");
    if (tr != parameters.end() && tr->second > 0)
      throw InputError("parameters.t_runup: the sieve's model variant '" + variant +
                       "' has no exciter run-up (only the default model file has one)");
    ModelForm form = ModelForm::closed_form;
    if (variant == "geometric") form = ModelForm::geometric;
    else if (variant == "analytic") form = ModelForm::analytic;
    else if (variant != "closed_form")
      throw InputError("the sieve has no model variant '" + variant + "'");
    return make_sieve_model(settings_from_table(case_table), form);
  }

 private:
  std::shared_ptr<const sim::ModelSource> shipped_;
};

}  // namespace

void register_sieve_variants() {
  static std::once_flag once;
  std::call_once(once, [] {
    register_sieve();
    auto shipped = sim::find_builtin("sieve");
    sim::register_builtin("sieve", [shipped] { return std::make_shared<const VariantSource>(shipped); });
  });
}

}  // namespace pcsim::sieve::testing
