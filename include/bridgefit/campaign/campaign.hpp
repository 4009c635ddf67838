#pragma once
// Test campaigns (issue 19): many specimens of one material, each through the
// single fit's chain (record -> R curve -> fit, pipeline::RunFit), specimens
// in parallel, then the statistics a paper reports.
//
//   manifest (io::ReadCampaignManifest) -> BuildRequests (every check, before
//   any work) -> RunCampaign (one RunFit per specimen on `jobs` threads; a
//   specimen that fails is data: its reason is kept, the others go on)
//   -> Summarise per parameter -> WriteCampaignOutputs
//
// Over MPI ranks (issue 20, docs/MPI.md): specimen i runs on rank i mod N
// (manifest order, so who runs what does not depend on timing); rank 0
// gathers every outcome with its fit file's bytes and alone computes the
// statistics, the joint fit and writes the outputs. A fit does not depend on
// the rank or thread that runs it, so the results are those of one process.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/io/campaign_manifest.hpp"
#include "bridgefit/parallel/communicator.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/pipeline/joint_fit.hpp"

namespace bridgefit::campaign {

struct CampaignOptions {
  int jobs = 0;  // specimens run at once; 0: the machine's cores
  // Called (from any worker, one call at a time) with one line per specimen
  // started and finished.
  std::function<void(const std::string& line)> progress;
  // After the separate fits: one law for every specimen that converged
  // (pipeline::RunJointFit) with the likelihood-ratio consistency test.
  bool joint = false;
  // The parameters the joint fit shares, over the manifest's `joint` key
  // (`campaign --joint-parameters`); none: the manifest's, else all.
  std::optional<inverse::SharedParameters> joint_parameters;
  // Profile threads of each fit (inverse::FitOptions::threads); 0: the
  // machine's cores / jobs, at least 1 (a request that sets its own wins).
  int fit_threads = 0;
  // The job's ranks; null: this process alone. With more than one, every
  // rank calls RunCampaign with the same manifest. In an MPI job (1 rank
  // too) `jobs` and the cores are per rank: the cores the rank is bound to,
  // or else its node's cores shared by the node's ranks.
  parallel::Communicator* communicator = nullptr;
  bool IsValid(std::string* why) const;
};

// A specimen's DIC on its images ([specimen.dic]), checked before any work
// (BuildDicRequests): the images in natural order and the options of
// `bridgefit dic` with the manifest's settings (dic::MakeSequenceOptions).
struct DicRequest {
  std::filesystem::path folder;
  std::vector<std::filesystem::path> images;
  dic::CrackSequenceOptions options;
};

struct SpecimenOutcome {
  std::string name;
  // With `dic`, RunCampaign sets request.frame_crack_lengths from its DIC.
  pipeline::FitRequest request;
  std::optional<DicRequest> dic;  // DIC first: its crack lengths go into the record
  // DIC ran: its /dic file (pipeline::WriteDicH5, the dic file's writer) as
  // bytes, written by the rank that ran it; WriteCampaignOutputs writes
  // them as specimens/dic/NAME.h5 and into campaign.h5 under /specimens/NAME.
  std::string dic_file;
  // DIC's per-frame warnings (flagged frames, frames without a length) and
  // how its frames were matched to the record's rows.
  std::vector<std::string> notes;
  std::optional<pipeline::FitRun> run;  // empty when the specimen could not run
  std::string error;                    // why it could not run (the Error's text)
  double wall_s = 0.0;
  int rank = 0;  // the MPI rank that ran it
  // Run on another rank: the fit file it wrote (WriteCampaignOutputs writes
  // these bytes as they are), and `run` holds what the campaign uses of the
  // fit: summary, data, law shape, R kind, element size, model note; its
  // input is read again on rank 0 for --joint (wire format:
  // src/campaign/outcome_wire.hpp).
  std::string fit_file;
  bool ran() const { return run.has_value(); }
  // Ran and the fit converged.
  bool ok() const { return run && run->summary.converged; }
};

// One parameter over the campaign. Values are the specimens that identify
// it; bounds the specimens that give only a lower bound (a truncated test).
struct ParameterStatistics {
  std::string parameter;  // sigma_c | J_B | delta_c | J_tip_c
  std::string unit;       // display unit of the numbers below
  double scale = 1.0;     // SI value x scale = display value
  int values = 0, bounds = 0;
  double mean = NAN, sd = NAN, cv = NAN;  // over the values (SD, CV with >= 2)
  double median = NAN;
  // The largest lower bound over the bound-only specimens: the campaign's
  // lower bound (NaN when no specimen gives a bound).
  double campaign_lower_bound = NAN;
  std::string bound_from;             // the specimen giving it
  std::vector<std::string> outliers;  // flagged, never dropped
  std::string note;                   // one sentence for the reader
};

// The outlier rule (stated in docs/CAMPAIGN.md): with at least 3 values, a
// value whose modified z-score 0.6745 |x - median| / MAD exceeds 3.5
// (Iglewicz and Hoaglin, 1993) is flagged; with MAD = 0, any value off the
// median by more than 1e-9 relative is.
inline constexpr double kOutlierModifiedZ = 3.5;

struct NamedEstimate {
  std::string specimen;
  inverse::ParameterEstimate estimate;
};
ParameterStatistics Summarise(const std::string& parameter, const std::string& unit, double scale,
                              const std::vector<NamedEstimate>& estimates);

struct CampaignResult {
  io::CampaignManifest manifest;
  std::vector<SpecimenOutcome> specimens;  // manifest order
  std::vector<ParameterStatistics> statistics;  // sigma_c, J_B, delta_c, J_tip_c
  int jobs = 1;   // threads per rank
  int ranks = 1;  // MPI ranks
  // False on a rank other than 0 of an MPI job: only its own specimens, no
  // statistics; such a result is not written (WriteCampaignOutputs refuses).
  bool complete = true;
  double wall_s = 0.0;
  // --joint: the joint fit, or why it could not run (a specimen that cannot
  // join, fewer than two converged).
  std::optional<pipeline::JointFitRun> joint;
  std::string joint_error;
  int Failed() const;  // specimens that did not run or did not converge
  std::string BriefReport() const;
};

// One fit request per specimen, in manifest order: every check that needs no
// fit (names of methods, laws and targets, the request's own IsValid). An
// error names the manifest, the specimen and the line.
std::vector<pipeline::FitRequest> BuildRequests(const io::CampaignManifest& manifest);
// The law parameters the joint fit shares ([campaign] joint; all when
// absent). An unknown name, delta_c, a name given twice or an empty list is
// an error naming the manifest, the line and the allowed names.
inverse::SharedParameters JointSharedParameters(const io::CampaignManifest& manifest);
// Per specimen (manifest order) its DIC request, or none without
// [specimen.dic]: the folder holds at least two images and the settings
// make valid options. An error names the manifest, the line and the key.
std::vector<std::optional<DicRequest>> BuildDicRequests(const io::CampaignManifest& manifest);

// Builds the requests (throws before any work), then runs them.
CampaignResult RunCampaign(const io::CampaignManifest& manifest, const CampaignOptions& options);

// The campaign of a manifest file on every rank of `comm` (`bridgefit
// campaign`, with or without mpirun; options.communicator is set to it).
// Each rank reads the manifest (a shared file system); a fault on any rank
// stops all before any work: rank 0 throws it (its own, or another rank's
// named), the others return `quiet_exit` (the exit code) and no result. An
// error on one rank mid-campaign cannot reach the others, which may wait in
// a transfer: it is printed on stderr and the whole job ended
// (Communicator::Abort(1)) before any output.
struct RankedCampaign {
  std::optional<CampaignResult> result;
  std::optional<int> quiet_exit;
};
RankedCampaign RunCampaignOnRanks(const std::string& manifest_path, CampaignOptions options,
                                  parallel::Communicator& comm);

// DIR/summary.csv (one row per specimen), DIR/statistics.csv (one row per
// parameter), with --joint DIR/joint.csv (one row per parameter and the
// consistency test's figures) and DIR/specimens/<name>.h5 (each a fit file, as `bridgefit fit
// --out` writes). Every file is written atomically; DIR is created.
void WriteCampaignOutputs(const CampaignResult& result, const std::filesystem::path& dir);

// campaign.h5 read back for `bridgefit design` (the reader beside its
// writer): the joint fit's law (/campaign/joint) with the specimen and
// material of its first specimen; without a joint fit, the fit of the
// specimen that gives the campaign's lower bound of J_B, else the first
// specimen with a fit. `note` says which. Throws Error(kInput) naming the
// file when it holds no fitted specimen.
pipeline::FittedLaw ReadCampaignLaw(const io::H5Reader& reader, const std::filesystem::path& file);

}  // namespace bridgefit::campaign
