#include "j_integral_flags.hpp"

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

namespace bridgefit::cli {

void JIntegralFlags::Add(CLI::App* sub) {
  sub->add_option("--scene", scene,
                  "Scene TOML: elastic constants for the tip fit (an orthotropic plate's "
                  "series) and, with --j-integral, the notch (the crack lengths must be "
                  "measured as the scene's notch is: use --offset)");
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

void JIntegralFlags::ApplyMaterial(dic::CrackSequenceOptions* options) const {
  if (scene.empty()) return;
  pipeline::TipMaterialFromScene(io::ReadSceneFile(scene), &options->tip);
}

}  // namespace bridgefit::cli
