// The MPI world (see mpi_world.hpp).  Built with MPI when CMake found it
// (NEARCAP_WITH_MPI), as a world of one otherwise.
#include "mpi_world.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#ifdef NEARCAP_WITH_MPI
#include <mpi.h>
#endif

namespace nearcap::cli {
namespace {

MpiWorld* g_world = nullptr;
std::unique_ptr<tbb::global_control> g_threads;  // this rank's share of a shared node

#ifdef NEARCAP_WITH_MPI
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (const char* s = std::getenv(v); s && *s) return true;
  return false;
}

int local_ranks() {
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "SLURM_NTASKS_PER_NODE"})
    if (const char* s = std::getenv(v); s && *s) return std::max(1, std::atoi(s));
  return 1;
}

constexpr int kRowsTag = 1;
#endif

}  // namespace

MpiWorld* mpi_world() { return g_world; }

MpiWorld::MpiWorld([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
  g_world = this;
#ifdef NEARCAP_WITH_MPI
  if (!launched_by_mpi()) return;
  MPI_Init(argc, argv);
  initialized_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  const int share = static_cast<int>(std::thread::hardware_concurrency()) / local_ranks();
  if (local_ranks() > 1)
    g_threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      static_cast<std::size_t>(std::max(1, share)));
#endif
}

MpiWorld::~MpiWorld() {
#ifdef NEARCAP_WITH_MPI
  if (initialized_) MPI_Finalize();
#endif
  g_threads.reset();
  g_world = nullptr;
}

bool MpiWorld::built_with_mpi() const {
#ifdef NEARCAP_WITH_MPI
  return true;
#else
  return false;
#endif
}

std::uint64_t MpiWorld::broadcast(std::uint64_t value) const {
#ifdef NEARCAP_WITH_MPI
  if (initialized_) {
    unsigned long long v = value;
    MPI_Bcast(&v, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    return v;
  }
#endif
  return value;
}

void MpiWorld::send_rows([[maybe_unused]] std::uint64_t index, [[maybe_unused]] const std::string& rows) const {
#ifdef NEARCAP_WITH_MPI
  if (initialized_) {
    std::vector<char> message(sizeof index + rows.size());
    std::memcpy(message.data(), &index, sizeof index);
    std::memcpy(message.data() + sizeof index, rows.data(), rows.size());
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kRowsTag, MPI_COMM_WORLD);
    return;
  }
#endif
  throw std::logic_error("send_rows without MPI");
}

bool MpiWorld::receive_rows([[maybe_unused]] std::uint64_t& index, [[maybe_unused]] std::string& rows,
                            [[maybe_unused]] bool wait) const {
#ifdef NEARCAP_WITH_MPI
  if (initialized_) {
    MPI_Status status;
    if (wait) {
      MPI_Probe(MPI_ANY_SOURCE, kRowsTag, MPI_COMM_WORLD, &status);
    } else {
      int ready = 0;
      MPI_Iprobe(MPI_ANY_SOURCE, kRowsTag, MPI_COMM_WORLD, &ready, &status);
      if (!ready) return false;
    }
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    std::vector<char> message(static_cast<std::size_t>(bytes));
    MPI_Recv(message.data(), bytes, MPI_BYTE, status.MPI_SOURCE, kRowsTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    std::memcpy(&index, message.data(), sizeof index);
    rows.assign(message.data() + sizeof index, message.size() - sizeof index);
    return true;
  }
#endif
  return false;
}

void MpiWorld::abort(int code) const {
#ifdef NEARCAP_WITH_MPI
  if (initialized_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace nearcap::cli
