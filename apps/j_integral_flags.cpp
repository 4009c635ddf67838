#include "j_integral_flags.hpp"

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

namespace bridgefit::cli {

void JIntegralFlags::Add(CLI::App* sub) {
  sub->add_option("--scene", scene,
                  "Scene TOML: elastic constants and notch for --j-integral (the crack lengths "
                  "must be measured as the scene's notch is: use --offset)");
  sub->add_flag("--j-integral", enabled,
                "Per frame: far-field J (domain integral) and the notch-root opening delta* "
                "(needs --scene; for `lawfree`)");
}

dic::FrameJOptions JIntegralFlags::Options() const {
  if (!enabled) return {};
  if (scene.empty())
    throw Error(ErrorKind::kUsage, "--j-integral needs --scene (elastic constants and notch)",
                {.field = "--j-integral", .expected = "--scene scene.toml"});
  return pipeline::FrameJOptionsFromScene(io::ReadSceneFile(scene));
}

}  // namespace bridgefit::cli
