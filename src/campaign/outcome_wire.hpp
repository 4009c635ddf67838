#pragma once
// A rank's specimen outcomes as bytes for rank 0 (issue 20, docs/MPI.md):
// the outcome (name, error, wall time), the fit file the rank wrote, and of
// the fit the parts the campaign uses on rank 0: the summary (every field,
// doubles bit for bit), the data fitted, the law shape, the R kind and the
// element size. The input is not sent: rank 0 reads it again for --joint.
// Ranks share one binary and byte order (one cluster).
#include <cstddef>
#include <string>
#include <vector>

#include "bridgefit/campaign/campaign.hpp"

namespace bridgefit::campaign::wire {

// The outcomes `indices` of `specimens` (each ran on this rank; its fit
// file's bytes already in `fit_file` when it ran), or, with `rank_error`
// not empty, why this rank cannot send them.
// `with_fit_files` false: the fit files are left out (sent empty).
std::string EncodeOutcomes(const std::vector<SpecimenOutcome>& specimens,
                           const std::vector<std::size_t>& indices,
                           const std::string& rank_error = "", bool with_fit_files = true);

// Fills the outcomes `bytes` holds into `specimens` (by manifest index,
// keeping each one's request). Throws Error (kRuntime) naming `from_rank`
// for a message that does not decode or carries the rank's error.
void DecodeOutcomes(const std::string& bytes, int from_rank,
                    std::vector<SpecimenOutcome>& specimens);

// More than one rank: every rank but 0 writes its specimens' fit files in a
// temporary folder of its own (removed after), and sends them with the
// outcomes to rank 0, which fills result.specimens. Collective.
void GatherOutcomes(CampaignResult& result, const std::vector<std::size_t>& mine,
                    parallel::Communicator& comm);

// After GatherOutcomes, for --joint on every rank: rank 0 broadcasts every
// specimen's outcome (fit files left out) and each other rank takes those
// it did not run (`mine`: those it did). Collective.
void ShareOutcomes(CampaignResult& result, const std::vector<std::size_t>& mine,
                   parallel::Communicator& comm);

}  // namespace bridgefit::campaign::wire
