#include "rcurve_flags.hpp"

#include "bridgefit/core/error.hpp"
#include "command.hpp"

namespace bridgefit::cli {

void ApplyRCurveFlags(const RCurveFlags& flags, const std::string& prefix,
                      experiment::RCurveOptions& options) {
  const std::string flag = "--" + prefix;
  try {
    options.method = experiment::ParseRMethod(flags.method);
  } catch (const Error& e) {
    throw Error(ErrorKind::kUsage, e.message(),
                {.field = flag + "method", .value = flags.method, .expected = e.context().expected});
  }
  if (!flags.min_increment.empty())
    options.min_crack_increment =
        ParseOptionQuantity(flags.min_increment, Dimension::Length(), flag + "min-increment");
  options.max_crack_length =
      ParseOptionQuantity(flags.max_crack_length, Dimension::Length(), flag + "max-crack-length");
  options.smoothing_half_window = flags.smooth_rows;
  options.load_noise = ParseOptionQuantity(flags.load_noise, Dimension::Force(), flag + "load-noise");
  options.displacement_noise = ParseOptionQuantity(flags.displacement_noise, Dimension::Length(),
                                                   flag + "displacement-noise");
  options.crack_length_noise =
      ParseOptionQuantity(flags.crack_noise, Dimension::Length(), flag + "crack-noise");
}

}  // namespace bridgefit::cli
