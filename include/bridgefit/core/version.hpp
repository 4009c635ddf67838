#pragma once
namespace bridgefit {
// Semantic version of the library and the CLI.
const char* VersionString();
}  // namespace bridgefit
