#pragma once
// The R-curve reduction flags shared by `bridgefit rcurve` (--method,
// --min-increment, ...) and `bridgefit fit RECORD` (the same behind the
// prefix --rcurve-): one mapping from their text to experiment::RCurveOptions.

#include <string>

#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::cli {

struct RCurveFlags {
  std::string method = "energy", min_increment, max_crack_length;
  std::string load_noise, displacement_noise, crack_noise;
  int smooth_rows = 0;
};

// Sets the reduction fields of `options` from `flags`; a malformed value is a
// usage error naming its flag, "--" + prefix + NAME (prefix "" or "rcurve-").
void ApplyRCurveFlags(const RCurveFlags& flags, const std::string& prefix,
                      experiment::RCurveOptions& options);

}  // namespace bridgefit::cli
