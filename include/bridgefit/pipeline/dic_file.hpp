#pragma once
// The output of `bridgefit dic` and `bridgefit crack`, its one owner: the
// per-frame CSV (crack length, tip, methods, flags) and the HDF5 /dic group
// (crack line, tips, opening profiles, fields), written and read here
// (docs/DIC.md). `rcurve --crack-length-from` and the report read through it.

#include <filesystem>
#include <string>
#include <vector>

#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/report/report_input.hpp"

namespace bridgefit::pipeline {

// `--csv`: one row per frame, lengths in mm, positions in px.
void WriteDicCsv(const std::string& path, const dic::CrackSequenceResult& result);
// `--out`: /dic (atomic: the file appears complete or not at all).
void WriteDicH5(const std::string& path, const dic::CrackSequenceResult& result,
                const dic::CrackSequenceOptions& options);

// The image and crack length [m] of each frame of a DIC CSV (NaN: no tip).
struct DicCrackLengths {
  std::vector<std::string> image;
  std::vector<double> crack_length;
};
// Throws Error(kInput) naming the file and the missing column.
DicCrackLengths ReadDicCrackLengths(const std::string& path);

// The report's view of a DIC run from its CSV and/or HDF5 (either may be
// empty): frames with tips, openings and why each is doubtful, the crack
// line, the images resolved on disk (recorded path, next to the DIC file, in
// `images_dir`). What could not be found goes to `notes`.
report::DicView ReadDicView(const std::filesystem::path& csv, const std::filesystem::path& h5,
                            const std::filesystem::path& images_dir,
                            std::vector<std::string>& notes);

}  // namespace bridgefit::pipeline
