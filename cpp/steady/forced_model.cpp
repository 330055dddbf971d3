#include "steady/forced_model.hpp"

namespace pcsim::steady {

ForcedModel::ForcedModel(std::shared_ptr<const mech::Model> inner, std::vector<int> coordinates,
                         Eigen::VectorXd H)
    : ForwardingModel(std::move(inner)), coordinates_idx_(std::move(coordinates)), H_(std::move(H)) {}

std::shared_ptr<const mech::Model> with_forces(std::shared_ptr<const mech::Model> inner,
                                               const std::vector<int>& coordinates,
                                               const Eigen::VectorXd& H) {
  if (coordinates.empty()) return inner;
  return std::make_shared<const ForcedModel>(std::move(inner), coordinates, H);
}

}  // namespace pcsim::steady
