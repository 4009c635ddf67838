// MPI_COMM_WORLD behind parallel::Communicator. Bytes travel as MPI_BYTE;
// ranks are assumed to share one binary and byte order (one cluster).
#include "mpi_communicator.hpp"

#include <mpi.h>

#include <climits>
#include <cstdint>
#include <cstdlib>
#include <numeric>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::parallel {
namespace {

// Throws Error (kRuntime) naming the MPI call and MPI's reason.
void Check(int code, const char* call) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING] = {};
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(ErrorKind::kRuntime, fmt::format("MPI failed ({}): {}", call, text),
              {.field = "MPI", .expected = "every rank of the job alive and reachable"});
}

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      Check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
      owns_mpi_ = true;
    }
    // Errors come back as codes (then Error), not MPI's default abort.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    Check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    Check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
    MPI_Comm node = MPI_COMM_NULL;
    Check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
          "MPI_Comm_split_type");
    Check(MPI_Comm_size(node, &local_size_), "MPI_Comm_size (node)");
    MPI_Comm_free(&node);
  }
  ~MpiCommunicator() override {
    if (owns_mpi_) MPI_Finalize();
  }
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int local_size() const override { return local_size_; }
  bool mpi() const override { return true; }
  std::string Describe() const override {
    return fmt::format("MPI ({} rank{}, {} on this node)", size_, size_ == 1 ? "" : "s",
                       local_size_);
  }

  std::vector<std::string> GatherToRoot(const std::string& bytes) override {
    // Sizes first (64-bit), then the bytes; MPI counts are int, so a rank's
    // message is limited to 2 GiB and the sum of them as well.
    const std::uint64_t own = bytes.size();
    std::vector<std::uint64_t> sizes(rank_ == 0 ? size_ : 0);
    Check(MPI_Gather(&own, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD),
          "MPI_Gather (sizes)");
    std::vector<int> counts, offsets;
    std::string all;
    if (rank_ == 0) {
      const std::uint64_t total = std::accumulate(sizes.begin(), sizes.end(), std::uint64_t{0});
      if (total > static_cast<std::uint64_t>(INT_MAX))
        throw Error(ErrorKind::kRuntime, "the ranks' results exceed one MPI message (2 GiB)",
                    {.field = "MPI_Gatherv", .value = fmt::format("{} bytes", total)});
      for (std::uint64_t s : sizes) {
        offsets.push_back(counts.empty() ? 0 : offsets.back() + counts.back());
        counts.push_back(static_cast<int>(s));
      }
      all.resize(total);
    }
    if (own > static_cast<std::uint64_t>(INT_MAX))
      throw Error(ErrorKind::kRuntime, "this rank's results exceed one MPI message (2 GiB)",
                  {.field = "MPI_Gatherv", .value = fmt::format("{} bytes", own)});
    Check(MPI_Gatherv(bytes.data(), static_cast<int>(own), MPI_BYTE, all.data(), counts.data(),
                      offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD),
          "MPI_Gatherv");
    std::vector<std::string> out;
    for (int k = 0; k < static_cast<int>(counts.size()); ++k)
      out.push_back(all.substr(offsets[k], counts[k]));
    return out;
  }

  std::string Broadcast(const std::string& bytes) override {
    std::uint64_t length = bytes.size();
    Check(MPI_Bcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast (size)");
    if (length > static_cast<std::uint64_t>(INT_MAX))
      throw Error(ErrorKind::kRuntime, "a broadcast exceeds one MPI message (2 GiB)",
                  {.field = "MPI_Bcast", .value = fmt::format("{} bytes", length)});
    std::string out = rank_ == 0 ? bytes : std::string(length, '\0');
    Check(MPI_Bcast(out.data(), static_cast<int>(length), MPI_BYTE, 0, MPI_COMM_WORLD),
          "MPI_Bcast");
    return out;
  }

 protected:
  void AbortJob(int exit_code) override { MPI_Abort(MPI_COMM_WORLD, exit_code); }

 private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
  bool owns_mpi_ = false;
};

}  // namespace

std::unique_ptr<Communicator> MakeMpiWorldCommunicator() {
  return std::make_unique<MpiCommunicator>();
}

}  // namespace bridgefit::parallel
