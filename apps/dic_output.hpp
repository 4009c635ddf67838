#pragma once
// Output of `bridgefit dic` and `bridgefit crack` (the same per-frame table,
// JSON object, CSV and HDF5 /dic layout; docs/DIC.md). Kept as functions so
// the HDF5 writer can move into a library.

#include <string>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::cli {

// Table on stdout, or one JSON object with --json. `field_unit`: the unit of
// the *_px values ("px" for images; the fields' unit for `crack`).
void PrintDicResult(const dic::CrackSequenceResult& result, const dic::CrackSequenceOptions& opt,
                    bool json, const std::string& field_unit = "px");
void WriteDicCsv(const std::string& path, const dic::CrackSequenceResult& result);
void WriteDicH5(const std::string& path, const dic::CrackSequenceResult& result,
                const dic::CrackSequenceOptions& opt);

}  // namespace bridgefit::cli
