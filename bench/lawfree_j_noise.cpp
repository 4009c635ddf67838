// What in the DIC makes the per-frame J_ff scatter of the law-free J route
// (docs/LAW_FREE.md, issue 21): one frame of a plain K field (no bridging:
// cheap to render; J = K^2 / E on any domain round the tip), rendered as
// `synth` renders (SpeckleRenderer, the same options), correlated as
// `bridgefit dic` does (the sequence's correlation options, crack band on
// the line) and integrated as `dic --j-integral` does (dic::ComputeFrameJ
// with the true tip), for several speckle patterns, image-noise draws and
// noise levels. The geometry is that of the law-free e2e test's last frame
// (400 x 320 px at 0.1 mm/px, tip 150 px past the notch root at 150 px).
//   lawfree_j_noise SCENE [PATTERNS]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/frame_j.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/settings.hpp"
#include "bridgefit/dic/speckle.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

using namespace bridgefit;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: lawfree_j_noise SCENE [PATTERNS]\n");
    return 2;
  }
  try {
    const Scene scene = io::ReadSceneFile(argv[1]);
    const int patterns = argc > 2 ? std::stoi(argv[2]) : 4;
    constexpr int kW = 400, kH = 320;
    constexpr double kScale = 0.1e-3, kOffset = 15e-3, kTipX = 300, kTipY = 160;
    const MaterialSpec& m = scene.material;
    const double mu = m.E / (2 * (1 + m.nu)), kappa = (3 - m.nu) / (1 + m.nu);
    const double K = 0.94e6;  // Pa m^0.5, about the e2e test's last frame
    const double J_true = K * K / m.E;

    dic::DicSettings settings;
    settings.scale_m_per_px = kScale;
    settings.offset_m = kOffset;
    settings.crack_line = dic::CrackLine{0, kTipY, kW - 1.0, kTipY};
    const dic::CrackSequenceOptions opt = dic::MakeSequenceOptions(settings);
    dic::CorrelationOptions copt = opt.correlation;
    copt.has_crack = true;
    copt.crack = opt.tip.line;
    dic::FrameJOptions jo = pipeline::FrameJOptionsFromScene(scene);
    // Variations (environment): BF_MARGIN (FrameJOptions::margin_points),
    // BF_SUBSET (px), BF_SHAPE2 (second-order subsets), BF_DOMAINS.
    if (const char* v = std::getenv("BF_MARGIN")) jo.margin_points = std::stod(v);
    if (const char* v = std::getenv("BF_DOMAINS")) jo.far_field_domains = std::stoi(v);
    if (const char* v = std::getenv("BF_SUBSET")) copt.subset_size = std::stoi(v);
    if (std::getenv("BF_SHAPE2")) copt.shape = dic::ShapeFunction::kSecondOrder;

    dic::ModeICrackField field;
    field.tip_x = kTipX;
    field.tip_y = kTipY;
    field.kappa = kappa;
    field.k_over_2mu = K / (2 * mu) / std::sqrt(kScale);
    field.translation_x = 4.5;
    field.translation_y = -3.0;
    auto j_error = [&](std::uint64_t pattern, double noise, int depth, std::uint64_t ref_seed,
                       std::uint64_t def_seed) {
      dic::SpeckleOptions so;
      so.width = kW;
      so.height = kH;
      so.speckle_radius_px = 2.0;
      so.seed = pattern;
      so.noise_std = noise;
      so.bit_depth = depth;
      const dic::SpeckleRenderer renderer(so);
      dic::Correlator correlator(copt, renderer.RenderReference(ref_seed * 1000));
      const dic::DisplacementField f =
          correlator.Next(renderer.Render(field, def_seed * 1000 + 15));
      const dic::FrameJ r = dic::ComputeFrameJ(f, kTipX, kTipY, kTipX, 1, 0,
                                               opt.tip.band_half_width_px, kScale, kOffset, jo);
      return r.status == dic::FrameJStatus::kOk ? 100 * (r.J_ff / J_true - 1) : NAN;
    };
    std::printf("J_ff error [%%] of one K-field frame (J = %.1f J/m^2), true tip\n", J_true);
    std::printf(
        "pattern  noise 0.005 8-bit: reference/deformed noise draws 1/1  1/2  2/1  2/2"
        "   noise 0 16-bit   noise 0.02 8-bit\n");
    for (int p = 1; p <= patterns; ++p)
      std::printf("%7d  %+8.2f %+8.2f %+8.2f %+8.2f  %+14.2f  %+14.2f\n", p,
                  j_error(p, 0.005, 8, 1, 1), j_error(p, 0.005, 8, 1, 2),
                  j_error(p, 0.005, 8, 2, 1), j_error(p, 0.005, 8, 2, 2), j_error(p, 0.0, 16, 1, 1),
                  j_error(p, 0.02, 8, 1, 1));
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
