#pragma once
// The fit file (`bridgefit fit --out fit.h5`), its one owner (writer and
// reader): the input's groups (/experiment and /rcurve,
// pipeline/rcurve_file.hpp) and /fit (the summary, the data and the model's
// fit to it, the parameters, the model check, the profiles, the law's shape
// in /fit/law_shape and the specimen and material the fit used in
// /fit/scene). Every dataset and attribute carries its units.

#include <filesystem>
#include <string>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/report/report_input.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::pipeline {

// Writes `run` to `path` atomically (the file appears complete or not at all).
void WriteFitFile(const std::string& path, const FitRequest& request, const FitRun& run);

// Reads /fit back as the report's view of it (its R curve from /rcurve when
// /fit holds none). Throws Error(kInput) naming the file and field for a
// missing file, no /fit group or no R curve.
report::FitView ReadFitView(const std::filesystem::path& path);

// The fitted law of a fit file with the specimen and material it was fitted
// on (what `bridgefit design` needs; SI). The estimates as written: a
// parameter reported as a bound has `identified` false and `lower_bound` set.
struct FittedLaw {
  std::string source;  // the file
  std::string group;   // the /fit group read, e.g. "/fit" or "/specimens/A/fit"
  std::string note;    // where the scene and law came from, for the reader
  Scene scene;         // specimen and material (bridging and fracture not set)
  laws::LawShape shape;
  inverse::ParameterEstimate sigma_c, J_B, delta_c, J_tip_c;
};

// True when `path` starts with the HDF5 signature.
bool IsHdf5File(const std::filesystem::path& path);

// Reads `root`/fit of an open fit-file layout (root "" for a fit file,
// "/specimens/NAME" inside a campaign.h5); `file` names it in messages. The
// specimen and material come from /fit/scene, or, in files written before
// it, from the scene file named by /fit's `scene` attribute (as given, then
// next to the fit file); the shape from /fit/law_shape, or the family's
// default. Throws Error(kInput) naming the file and what is expected when
// there is no /fit group (an R-curve file says so), no fitted sigma_c or
// J_B (value or bound), or no specimen.
FittedLaw ReadFittedLaw(const io::H5Reader& reader, const std::filesystem::path& file,
                        const std::string& root = "");
// The same from a fit file on disk; also throws for a missing or non-HDF5 file.
FittedLaw ReadFittedLaw(const std::filesystem::path& path);

}  // namespace bridgefit::pipeline
