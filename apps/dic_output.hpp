#pragma once
// Printed output of `bridgefit dic` and `bridgefit crack` (the same per-frame
// table and JSON object; docs/DIC.md). Their files: pipeline/dic_file.hpp.

#include <string>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::cli {

// Table on stdout, or one JSON object with --json. `field_unit`: the unit of
// the *_px values ("px" for images; the fields' unit for `crack`).
void PrintDicResult(const dic::CrackSequenceResult& result, const dic::CrackSequenceOptions& opt,
                    bool json, const std::string& field_unit = "px");

}  // namespace bridgefit::cli
