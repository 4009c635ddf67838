#pragma once
// `bridgefit crack` as a library call: crack lengths from displacement
// fields exported by other DIC software (docs/DIC.md), the files checked
// in a bounded child first where their reader can crash or run away.

#include <string>
#include <vector>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::pipeline {

struct CrackFieldsRequest {
  std::vector<std::string> fields;    // files, folders or globs (dic::ExpandFieldArguments)
  dic::CrackSequenceOptions options;  // scale (fields in px), line, tip method, J integral
  dic::FieldSettings settings;        // band, Williams radius, threshold in the fields' unit
};

struct CrackFieldsRun {
  dic::CrackSequenceResult result;
  dic::CrackSequenceOptions used;  // as applied (for the /dic writer)
};

// Expands the arguments, reads every Ncorr MAT file once in a child process
// (10 s + 1 s per 10 MB: a corrupt v7.3 file can crash libhdf5, a v5 header
// can make matio allocate gigabytes), then dic::AnalyzeCrackFields. Throws
// Error naming the file for bad input.
CrackFieldsRun RunCrackFields(const CrackFieldsRequest& request);

}  // namespace bridgefit::pipeline
