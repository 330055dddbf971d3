// The MPI job this process belongs to, and the few messages a distributed sweep exchanges.
// Without PCSIM_WITH_MPI, or when not launched by mpirun, it is a one-rank cluster and every
// operation is local. All calls are made from the thread that created the Cluster
// (MPI_THREAD_FUNNELED); worker threads never touch MPI.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

namespace pcsim::study {

class Cluster {
 public:
  /// Joins the MPI job when MPI is built in and the process was started by mpirun/mpiexec
  /// (detected from the launcher's environment: OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK);
  /// initializes MPI unless it already is, and finalizes it in the destructor if it did.
  Cluster();
  ~Cluster();
  Cluster(const Cluster&) = delete;
  Cluster& operator=(const Cluster&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Rank 0's `text` delivered to every rank (the argument is ignored on other ranks).
  std::string broadcast(const std::string& text) const;
  /// Sends one finished sweep row (grid index and CSV line) to rank 0. Not for rank 0.
  void send_row(std::size_t index, const std::string& line) const;
  /// On rank 0: one row sent by another rank, if one has arrived; nullopt otherwise.
  std::optional<std::pair<std::size_t, std::string>> poll_row() const;

 private:
  int rank_ = 0;
  int size_ = 1;
  bool finalize_ = false;
};

}  // namespace pcsim::study
