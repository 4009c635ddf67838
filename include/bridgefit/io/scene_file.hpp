#pragma once
// Reads a scene TOML file (format: docs/FORMATS.md). Unknown and missing
// keys are errors naming the file, line and key; values carry units.

#include <filesystem>
#include <string_view>

#include "bridgefit/scene/scene.hpp"

namespace bridgefit::io {

Scene ReadSceneFile(const std::filesystem::path& path);
// Parses scene text; `source_name` is used in messages.
Scene ParseScene(std::string_view text, const std::string& source_name);

}  // namespace bridgefit::io
