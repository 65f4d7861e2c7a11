// The MPI world a sweep runs in (Open MPI through mpirun or a batch system's
// launcher), or a world of one process when nearcap is built without MPI or
// started without a launcher.  Only the sweep command uses it: it shards the
// configurations across ranks and rank 0 gathers their rows (sweep_command.cpp).
#pragma once

#include <cstdint>
#include <string>

namespace nearcap::cli {

class MpiWorld {
 public:
  // MPI_Init when a launcher started this process (its environment says so:
  // OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_RANK), a world of one otherwise.
  // On a node shared by several ranks, each rank's TBB threads are limited to
  // its share of the node's cores.
  MpiWorld(int* argc, char*** argv);
  ~MpiWorld();  // MPI_Finalize
  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool built_with_mpi() const;

  // Rank 0 decides, every rank gets the value.
  std::uint64_t broadcast(std::uint64_t value) const;
  // A worker's rows of configuration `index`, to rank 0 (blocking).
  void send_rows(std::uint64_t index, const std::string& rows) const;
  // Rank 0: the next rows from any worker; `wait` false returns false when
  // none has arrived yet.
  bool receive_rows(std::uint64_t& index, std::string& rows, bool wait) const;
  // Ends every rank (after a rank failed and reported why).
  [[noreturn]] void abort(int code) const;

  // From here on the ranks work apart: an error on one rank must end all
  // (main aborts the world); before, every rank meets the same errors (bad
  // options) and only rank 0 reports them.
  void mark_sharded() { sharded_ = true; }
  bool sharded() const { return sharded_; }

 private:
  int rank_ = 0, size_ = 1;
  bool initialized_ = false, sharded_ = false;
};

// The process's world, once main made it (nullptr in library tests).
MpiWorld* mpi_world();

}  // namespace nearcap::cli
