#pragma once
// --scene / --j-integral, shared by `bridgefit dic` and `bridgefit crack`:
// per frame far-field J and the notch-root opening delta* (for `lawfree`).

#include <string>

#include <CLI/CLI.hpp>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::cli {

struct JIntegralFlags {
  std::string scene;
  bool enabled = false;
  void Add(CLI::App* sub);
  // The sequence's J options from the scene (disabled without --j-integral);
  // --j-integral without --scene is a usage error naming both flags.
  dic::FrameJOptions Options() const;
  // The scene's elastic constants for the tip fit (with or without
  // --j-integral); nothing without --scene.
  void ApplyMaterial(dic::CrackSequenceOptions* options) const;
};

}  // namespace bridgefit::cli
