#pragma once
// Processes that share one job (issue 20): a campaign's specimens spread over
// the ranks of an MPI launch (`mpirun -n N bridgefit campaign ...`). MPI stays
// behind this interface (src/parallel/mpi_communicator.cpp, built only with
// BRIDGEFIT_MPI); without it, or when the process was not started by an MPI
// launcher, the communicator is the process alone (rank 0 of 1).
//
// Every call below is collective: each rank of the communicator makes it, in
// the same order. A failed transfer throws Error (kRuntime) naming the call
// and MPI's reason; a rank that dies ends the whole job (mpirun's default),
// so no rank waits forever.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace bridgefit::parallel {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Ranks on this rank's node (they share its cores), 1 for the serial one.
  virtual int local_size() const = 0;
  // "serial" or "MPI (3 ranks, 3 on this node)".
  virtual std::string Describe() const = 0;
  // An MPI job's (of 1 rank too): the launcher may have bound it to cores.
  virtual bool mpi() const = 0;
  bool root() const { return rank() == 0; }

  // Every rank's bytes, in rank order, on rank 0; empty on the others.
  virtual std::vector<std::string> GatherToRoot(const std::string& bytes) = 0;
  // Rank 0's bytes on every rank.
  virtual std::string Broadcast(const std::string& bytes) = 0;
  // Every rank's bytes, in rank order, on every rank (a gather to rank 0,
  // then its broadcast). For work dealt over the ranks that each rank
  // continues from (a joint fit's profiles, docs/MPI.md).
  std::vector<std::string> AllGather(const std::string& bytes);
  // The rank that does item `item` of work dealt round-robin: item mod N,
  // so the assignment depends only on N.
  int OwnerOf(std::size_t item) const { return static_cast<int>(item % size()); }
  // Ends every rank of the job with `exit_code` (after an error on one rank
  // that the others cannot know about).
  [[noreturn]] void Abort(int exit_code);

  // The first non-empty `error` in rank order, on every rank ("" when every
  // rank passed ""); another rank's error is prefixed "rank K: ". For a step
  // each rank does alone (reading the manifest) that must stop all or none.
  std::string FirstError(const std::string& error);

 protected:
  // Abort's work (MPI_Abort); Abort ends this process if it returns.
  virtual void AbortJob(int exit_code) = 0;
};

// This process alone.
std::unique_ptr<Communicator> MakeSerialCommunicator();

// Whether this bridgefit was built with MPI (BRIDGEFIT_MPI).
bool MpiBuilt();
// The number of ranks an MPI launcher (mpirun, mpiexec, srun with PMI/PMIx)
// started, read from its environment; 0 when not started by one.
int LaunchedRanks();

// The job's world: with MPI built and an MPI launch, MPI is initialised here
// and finalised when the communicator is destroyed (one per process);
// otherwise the serial communicator. Throws Error (kUsage) when a launcher
// started more than one rank of a bridgefit built without MPI (every rank
// would run everything and write the same outputs).
std::unique_ptr<Communicator> MakeWorldCommunicator();

}  // namespace bridgefit::parallel
