#include "bridgefit/core/version.hpp"
namespace bridgefit {
const char* VersionString() { return BRIDGEFIT_VERSION; }
}  // namespace bridgefit
