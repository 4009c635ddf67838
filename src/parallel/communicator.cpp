// The serial communicator, the launcher's environment and the world factory.
#include "bridgefit/parallel/communicator.hpp"

#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/parallel/bytes.hpp"
#include "mpi_communicator.hpp"

namespace bridgefit::parallel {
namespace {

class SerialCommunicator final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  int local_size() const override { return 1; }
  std::string Describe() const override { return "serial"; }
  bool mpi() const override { return false; }
  std::vector<std::string> GatherToRoot(const std::string& bytes) override { return {bytes}; }
  std::string Broadcast(const std::string& bytes) override { return bytes; }

 protected:
  void AbortJob(int) override {}
};

// A positive integer from the environment, 0 when unset or not one.
int EnvironmentCount(const char* name) {
  const char* text = std::getenv(name);
  if (!text || !*text) return 0;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  return end && *end == '\0' && value > 0 && value < (1L << 30) ? static_cast<int>(value) : 0;
}

}  // namespace

void Communicator::Abort(int exit_code) {
  AbortJob(exit_code);
  std::_Exit(exit_code);
}

std::string Communicator::FirstError(const std::string& error) {
  if (size() == 1) return error;
  const std::vector<std::string> errors = GatherToRoot(error);
  std::string first;
  for (std::size_t k = 0; k < errors.size() && first.empty(); ++k)
    if (!errors[k].empty()) first = k == 0 ? errors[k] : fmt::format("rank {}: {}", k, errors[k]);
  return Broadcast(first);
}

std::vector<std::string> Communicator::AllGather(const std::string& bytes) {
  if (size() == 1) return {bytes};
  ByteWriter all;
  if (root()) {
    const std::vector<std::string> parts = GatherToRoot(bytes);
    all.Items(parts, [](ByteWriter& io, const std::string& part) { io.Field(part); });
  } else {
    GatherToRoot(bytes);
  }
  const std::string message = Broadcast(all.Take());
  std::vector<std::string> parts;
  ByteReader in(message, "gathered messages", 0);
  in.Items(parts, [](ByteReader& io, std::string& part) { io.Field(part); });
  if (!in.done() || static_cast<int>(parts.size()) != size()) in.Corrupt();
  return parts;
}

std::unique_ptr<Communicator> MakeSerialCommunicator() {
  return std::make_unique<SerialCommunicator>();
}

bool MpiBuilt() {
#ifdef BRIDGEFIT_HAVE_MPI
  return true;
#else
  return false;
#endif
}

int LaunchedRanks() {
  // Open MPI's mpirun, MPICH / Intel MPI (Hydra, PMI-1/2), MVAPICH.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MV2_COMM_WORLD_SIZE"})
    if (const int n = EnvironmentCount(name)) return n;
  // PMIx (srun --mpi=pmix) names the rank, not the size: MPI tells it.
  if (std::getenv("PMIX_RANK")) return 1;
  return 0;
}

namespace {

// srun started several tasks that MPI does not join (no PMI/PMIx plugin, or
// a build without MPI): each would run the whole job and write the same files.
void CheckSlurmTasks(int mpi_ranks) {
  const int tasks = EnvironmentCount("SLURM_STEP_NUM_TASKS");
  if (tasks > 1 && mpi_ranks == 1)
    throw Error(ErrorKind::kUsage,
                fmt::format("srun started {} tasks, but they are not one MPI job: every task "
                            "would run the whole job",
                            tasks),
                {.field = "srun -n", .value = std::to_string(tasks),
                 .expected = MpiBuilt() ? "srun --mpi=pmix (or pmi2), or mpirun"
                                        : "a build with -DBRIDGEFIT_MPI=ON"});
}

}  // namespace

std::unique_ptr<Communicator> MakeWorldCommunicator() {
  const int launched = LaunchedRanks();
#ifdef BRIDGEFIT_HAVE_MPI
  if (launched > 0) {
    std::unique_ptr<Communicator> world = MakeMpiWorldCommunicator();
    CheckSlurmTasks(world->size());
    return world;
  }
#else
  if (launched > 1)
    throw Error(ErrorKind::kUsage,
                fmt::format("started by an MPI launcher as {} ranks, but this bridgefit was built "
                            "without MPI: every rank would run the whole job",
                            launched),
                {.field = "mpirun -n",
                 .value = std::to_string(launched),
                 .expected = "a build with -DBRIDGEFIT_MPI=ON (libopenmpi-dev), or one process "
                             "(--jobs N for threads)"});
#endif
  CheckSlurmTasks(1);
  return MakeSerialCommunicator();
}

}  // namespace bridgefit::parallel
