#include "sim/client.hpp"

#include <map>
#include <mutex>

namespace pcsim::sim {

namespace {
std::mutex& clients_mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::shared_ptr<const Client>>& clients() {
  static std::map<std::string, std::shared_ptr<const Client>> c;
  return c;
}
}  // namespace

void register_client(const std::string& model_name, std::shared_ptr<const Client> client) {
  std::lock_guard<std::mutex> lock(clients_mutex());
  clients()[model_name] = std::move(client);
}

std::shared_ptr<const Client> find_client(const std::string& model_name) {
  std::lock_guard<std::mutex> lock(clients_mutex());
  auto it = clients().find(model_name);
  return it == clients().end() ? nullptr : it->second;
}

}  // namespace pcsim::sim
