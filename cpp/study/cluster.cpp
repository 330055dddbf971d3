// One-rank or MPI cluster: initialization, broadcast, and row messages to rank 0.
#include "study/cluster.hpp"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#ifdef PCSIM_WITH_MPI
#define OMPI_SKIP_MPICXX 1  // the C API only: no deprecated C++ bindings
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace pcsim::study {

#ifdef PCSIM_WITH_MPI

namespace {
constexpr int kRowTag = 61;

bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") ||
         std::getenv("PMIX_RANK");
}
}  // namespace

Cluster::Cluster() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    if (!launched_by_mpirun()) return;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    finalize_ = true;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Cluster::~Cluster() {
  if (finalize_) MPI_Finalize();
}

std::string Cluster::broadcast(const std::string& text) const {
  if (size_ == 1) return text;
  unsigned long long n = rank_ == 0 ? text.size() : 0;
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  std::string out = rank_ == 0 ? text : std::string(n, '\0');
  if (n > 0) MPI_Bcast(out.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
  return out;
}

void Cluster::send_row(std::size_t index, const std::string& line) const {
  std::vector<char> msg(sizeof(std::uint64_t) + line.size());
  const std::uint64_t i = index;
  std::memcpy(msg.data(), &i, sizeof i);
  std::memcpy(msg.data() + sizeof i, line.data(), line.size());
  MPI_Send(msg.data(), static_cast<int>(msg.size()), MPI_CHAR, 0, kRowTag, MPI_COMM_WORLD);
}

std::optional<std::pair<std::size_t, std::string>> Cluster::poll_row() const {
  if (size_ == 1) return std::nullopt;
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, kRowTag, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return std::nullopt;
  int count = 0;
  MPI_Get_count(&status, MPI_CHAR, &count);
  std::vector<char> msg(static_cast<std::size_t>(count));
  MPI_Recv(msg.data(), count, MPI_CHAR, status.MPI_SOURCE, kRowTag, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  std::uint64_t i = 0;
  std::memcpy(&i, msg.data(), sizeof i);
  return std::make_pair(static_cast<std::size_t>(i),
                        std::string(msg.data() + sizeof i, msg.size() - sizeof i));
}

#else  // one process: every operation is local

Cluster::Cluster() = default;
Cluster::~Cluster() = default;
std::string Cluster::broadcast(const std::string& text) const { return text; }
void Cluster::send_row(std::size_t, const std::string&) const {}
std::optional<std::pair<std::size_t, std::string>> Cluster::poll_row() const {
  return std::nullopt;
}

#endif

}  // namespace pcsim::study
