// A campaign over MPI ranks (issue 20): every rank's outcomes to rank 0.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/campaign_manifest.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "outcome_wire.hpp"

namespace bridgefit::campaign::wire {
namespace {

namespace fs = std::filesystem;

// A rank's own temporary folder, removed with everything in it.
struct RankFolder {
  fs::path path;
  explicit RankFolder(int rank)
      : path(fs::temp_directory_path() /
             fmt::format("bf_campaign_rank{}_{}", rank, static_cast<long>(::getpid()))) {
    fs::remove_all(path);
    std::error_code ec;
    fs::create_directories(path, ec);
    if (ec)
      throw Error(ErrorKind::kRuntime, "cannot create this rank's temporary folder",
                  {.file = path.string(), .value = ec.message()});
  }
  ~RankFolder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  RankFolder(const RankFolder&) = delete;
  RankFolder& operator=(const RankFolder&) = delete;
};

std::string FileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof())
    throw Error(ErrorKind::kRuntime, "cannot read back a fit file this rank wrote",
                {.file = path.string()});
  return bytes;
}

// This rank's fit files, written by the fit file's owner as rank 0 would.
void AttachFitFiles(CampaignResult& result, const std::vector<std::size_t>& mine, int rank) {
  const RankFolder folder(rank);
  for (std::size_t i : mine) {
    SpecimenOutcome& s = result.specimens[i];
    if (!s.ran()) continue;
    const fs::path path = folder.path / fmt::format("specimen_{}.h5", i);
    pipeline::WriteFitFile(path.string(), s.request, *s.run);
    s.fit_file = FileBytes(path);
  }
}

}  // namespace

void GatherOutcomes(CampaignResult& result, const std::vector<std::size_t>& mine,
                    parallel::Communicator& comm) {
  std::string message;
  if (!comm.root()) {
    // A failure here is the campaign's, sent to rank 0 rather than thrown
    // (rank 0 waits for this message).
    try {
      AttachFitFiles(result, mine, comm.rank());
      message = EncodeOutcomes(result.specimens, mine);
    } catch (const Error& e) {
      message = EncodeOutcomes(result.specimens, {}, e.what());
    }
  }
  const std::vector<std::string> messages = comm.GatherToRoot(message);
  for (std::size_t k = 1; k < messages.size(); ++k)
    DecodeOutcomes(messages[k], static_cast<int>(k), result.specimens);
}

void ShareOutcomes(CampaignResult& result, const std::vector<std::size_t>& mine,
                   parallel::Communicator& comm) {
  std::vector<std::size_t> all(result.specimens.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const std::string message =
      comm.Broadcast(comm.root() ? EncodeOutcomes(result.specimens, all, "", false) : "");
  if (comm.root()) return;
  std::vector<SpecimenOutcome> received(result.specimens.size());
  for (std::size_t i = 0; i < received.size(); ++i) received[i].name = result.specimens[i].name;
  DecodeOutcomes(message, 0, received);
  for (std::size_t i = 0; i < received.size(); ++i) {
    if (std::find(mine.begin(), mine.end(), i) != mine.end()) continue;
    SpecimenOutcome& s = result.specimens[i];
    s.run = std::move(received[i].run);
    s.error = std::move(received[i].error);
    s.wall_s = received[i].wall_s;
    s.rank = received[i].rank;
    s.notes = std::move(received[i].notes);
    s.request.frame_crack_lengths = std::move(received[i].request.frame_crack_lengths);
  }
}

}  // namespace bridgefit::campaign::wire

namespace bridgefit::campaign {
namespace {

// Each rank reads the manifest; a fault on any rank stops all (above).
std::optional<int> ReadOnEveryRank(const std::string& path, parallel::Communicator& comm,
                                   io::CampaignManifest& manifest) {
  std::optional<Error> own;
  try {
    manifest = io::ReadCampaignManifest(path);
    BuildRequests(manifest);
    BuildDicRequests(manifest);
    JointSharedParameters(manifest);
  } catch (const Error& e) {
    own = e;
  }
  const std::string first = comm.FirstError(own ? own->what() : "");
  if (first.empty()) return std::nullopt;
  if (!comm.root()) return own && own->kind() == ErrorKind::kUsage ? 2 : 1;
  if (own) throw *own;
  throw Error(ErrorKind::kInput, first, {.file = path, .field = "manifest on another rank"});
}

}  // namespace

RankedCampaign RunCampaignOnRanks(const std::string& manifest_path, CampaignOptions options,
                                  parallel::Communicator& comm) {
  options.communicator = &comm;
  RankedCampaign out;
  io::CampaignManifest manifest;
  if (comm.size() == 1) {
    manifest = io::ReadCampaignManifest(manifest_path);
    out.result = RunCampaign(manifest, options);
    return out;
  }
  if (const std::optional<int> code = ReadOnEveryRank(manifest_path, comm, manifest)) {
    out.quiet_exit = code;  // a manifest fault: rank 0 reports it, the others end quietly
    return out;
  }
  try {
    out.result = RunCampaign(manifest, options);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::kInterrupted) throw;
    std::cerr << "bridgefit campaign: error on MPI rank " << comm.rank() << " of " << comm.size()
              << ": " << e.what() << "\n  the job is ended; no output written.\n";
    comm.Abort(1);
  }
  return out;
}

}  // namespace bridgefit::campaign
