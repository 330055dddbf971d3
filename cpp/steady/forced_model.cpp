#include "steady/forced_model.hpp"

namespace pcsim::steady {

ForcedModel::ForcedModel(std::shared_ptr<const mech::Model> inner, std::vector<int> coordinates,
                         Eigen::VectorXd H)
    : inner_(std::move(inner)), coordinates_idx_(std::move(coordinates)), H_(std::move(H)) {
  name_ = inner_->name();
  coordinates_ = inner_->coordinates();
  constraints_ = inner_->constraints();
  derived_names_ = inner_->derived_names();
}

std::shared_ptr<const mech::Model> with_forces(std::shared_ptr<const mech::Model> inner,
                                               const std::vector<int>& coordinates,
                                               const Eigen::VectorXd& H) {
  if (coordinates.empty()) return inner;
  return std::make_shared<const ForcedModel>(std::move(inner), coordinates, H);
}

}  // namespace pcsim::steady
