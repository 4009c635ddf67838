// libFuzzer harness: scene TOML (io/scene_file.cpp), including the table law
// it may name (resolved next to a scene path that does not exist).
#include <cstddef>
#include <cstdint>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)bridgefit::io::ParseScene(text, "/nonexistent-fuzz-dir/scene.toml");
  } catch (const bridgefit::Error&) {
  }
  return 0;
}
