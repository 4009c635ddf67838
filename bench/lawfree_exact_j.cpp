// Where the per-frame J_ff scatter of the law-free J route comes from
// (docs/LAW_FREE.md, issue 21). On a `synth --bridged-field` run (DIR/images
// with truth.csv), the DIC is run in process (the `bridgefit dic --scene S
// --j-integral` defaults) and each frame's J_ff is computed four ways by the
// same unit (dic::ComputeFrameJ: domains, crack band, gradient fit):
//   DIC field, DIC tip       (what `bridgefit dic` writes)
//   DIC field, true tip      (the tip's share)
//   exact field, DIC tip     (the generator's displacement at the same grid
//                             points with the same statuses: no DIC error)
//   exact field, true tip    (the integral's own discretisation error)
// against the generator's J_ff. The exact field is the generator's bridged
// crack rebuilt from truth.csv (K_I, tip, rigid motion, zone) and the scene's
// law; frame 1 (no zone yet) is the plain K field.
//   lawfree_exact_j DIR SCENE [WIDTH HEIGHT]
// Environment: BF_FIT_LO, BF_FIT_HI, BF_FIT_MARGIN, BF_FIT_LAG (the field
// fit's orders, extra circle points, HAC lags); BF_EXACT_BOX=M (the exact
// field averaged over M x M px squares, as a first-order subset reads it);
// BF_ERR_MAP=1 (the last frame's mean DIC error in 40 px cells);
// BF_HYBRID=1 (the fit's J on the exact field with the DIC's values in one
// region only: near / mid / far from the crack line, behind / ahead of the tip).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/frame_j.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/settings.hpp"
#include "bridgefit/dic/speckle.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

namespace fs = std::filesystem;
using namespace bridgefit;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: lawfree_exact_j DIR SCENE [WIDTH HEIGHT]\n");
    return 2;
  }
  try {
    const fs::path dir = argv[1];
    const Scene scene = io::ReadSceneFile(argv[2]);
    const int width = argc > 4 ? std::stoi(argv[3]) : 400,
              height = argc > 4 ? std::stoi(argv[4]) : 320;
    constexpr double kScale = 0.1e-3, kOffset = 15e-3;
    const laws::BridgingLaw law = scene.bridging->Law();
    const MaterialSpec& m = scene.material;
    const double mu = m.E / (2 * (1 + m.nu));
    const double kappa = (3 - m.nu) / (1 + m.nu);  // plane stress (the bench's scenes)

    dic::DicSettings settings;
    settings.scale_m_per_px = kScale;
    settings.offset_m = kOffset;
    settings.crack_line = dic::CrackLine{0, 0.5 * height, width - 1.0, 0.5 * height};
    dic::CrackSequenceOptions opt = dic::MakeSequenceOptions(settings);
    opt.keep_fields = true;
    opt.j_integral = pipeline::FrameJOptionsFromScene(scene);
    if (const char* e = std::getenv("BF_FIT_LO")) opt.j_integral.fit.lowest_order = std::atoi(e);
    if (const char* e = std::getenv("BF_FIT_HI")) opt.j_integral.fit.highest_order = std::atoi(e);
    if (const char* e = std::getenv("BF_FIT_MARGIN")) opt.j_integral.fit_margin_points = std::atof(e);
    if (const char* e = std::getenv("BF_FIT_LAG")) opt.j_integral.fit.correlation_lag = std::atoi(e);
    std::vector<fs::path> images;
    for (int k = 0; fs::exists(dir / "images" / fmt::format("frame_{:02d}.png", k)); ++k)
      images.push_back(dir / "images" / fmt::format("frame_{:02d}.png", k));
    const dic::CrackSequenceResult run = dic::AnalyzeCrackSequence(images, opt);

    const io::CsvTable truth = io::ReadCsvTable(dir / "images" / "truth.csv");
    const auto crack = truth.ColumnSi("crack_length", Dimension::Length());
    const auto tip_x = truth.columns[truth.Find("tip_x")],
               tip_y = truth.columns[truth.Find("tip_y")];
    const auto K = truth.columns[truth.Find("K_I")];
    const auto tx = truth.columns[truth.Find("translation_x")];
    const auto ty = truth.columns[truth.Find("translation_y")];
    const auto J = truth.columns[truth.Find("J_ff")];
    std::printf(
        "frame  zone[mm]  tip err[px]  J err [%%]: DIC/DIC tip  DIC/true tip  exact/DIC tip  "
        "exact/true tip\n");
    double ss[4] = {0, 0, 0, 0}, fss[4] = {0, 0, 0, 0}, zss[4] = {0, 0, 0, 0};
    int n = 0;
    for (size_t k = 1; k < run.frames.size() && k < J.size(); ++k) {
      const dic::FrameResult& f = run.frames[k];
      if (f.j.status != dic::FrameJStatus::kOk || !f.tip.tip.found) continue;
      const double zone_px = (crack[k] - scene.specimen.notch) / kScale;
      const double k2mu = K[k] * 1e6 / (2 * mu) / std::sqrt(kScale);
      dic::DisplacementField exact = f.field;
      // BF_EXACT_BOX=M: the exact field averaged over an M x M px square
      // about each point (5 x 5 Gauss points), as a first-order subset
      // reads a curved field (DIC smoothing without image noise).
      const double box = std::getenv("BF_EXACT_BOX") ? std::atof(std::getenv("BF_EXACT_BOX")) : 0;
      auto boxed = [&](auto& model) {
        static const double g5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                     0.5384693101056831, 0.9061798459386640};
        static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                     0.4786286704993665, 0.2369268850561891};
        for (size_t i = 0; i < exact.size(); ++i) {
          if (box <= 0) {
            model(exact.x[i], exact.y[i], &exact.u[i], &exact.v[i]);
            continue;
          }
          double su = 0, sv = 0;
          for (int a = 0; a < 5; ++a)
            for (int b = 0; b < 5; ++b) {
              double uu, vv;
              model(exact.x[i] + 0.5 * box * g5[a], exact.y[i] + 0.5 * box * g5[b], &uu, &vv);
              su += 0.25 * w5[a] * w5[b] * uu;
              sv += 0.25 * w5[a] * w5[b] * vv;
            }
          exact.u[i] = su;
          exact.v[i] = sv;
        }
      };
      if (zone_px > 0.5) {
        dic::BridgedCrackField b;
        b.tip_x = tip_x[k];
        b.tip_y = tip_y[k];
        b.kappa = kappa;
        b.translation_x = tx[k];
        b.translation_y = ty[k];
        b.zone_length = zone_px;
        b.segments = 120;
        b.k_over_2mu = k2mu;
        b.traction_over_2mu = [&](double d) { return law.Traction(d * kScale) / (2 * mu); };
        b.Solve();
        boxed(b);
      } else {
        dic::ModeICrackField e;
        e.tip_x = tip_x[k];
        e.tip_y = tip_y[k];
        e.kappa = kappa;
        e.k_over_2mu = k2mu;
        e.translation_x = tx[k];
        e.translation_y = ty[k];
        boxed(e);
      }
      double du2 = 0, dv2 = 0;
      int ok = 0;
      for (size_t i = 0; i < exact.size(); ++i)
        if (f.field.ok(i)) {
          du2 += std::pow(f.field.u[i] - exact.u[i], 2),
              dv2 += std::pow(f.field.v[i] - exact.v[i], 2);
          ++ok;
        }
      if (std::getenv("BF_ERR_MAP") && k == run.frames.size() - 1) {
        // Mean v and u error [1e-4 px] in 40 x 40 px cells (rows top to bottom).
        for (int comp = 0; comp < 2; ++comp) {
          std::printf("  %s error map [1e-4 px], frame %zu, tip (%.0f, %.0f)\n", comp ? "u" : "v", k,
                      tip_x[k], tip_y[k]);
          for (int cy = 0; cy * 40 < height; ++cy) {
            std::printf("  y%4d", cy * 40);
            for (int cx = 0; cx * 40 < width; ++cx) {
              double sum = 0;
              int cnt = 0;
              for (size_t i = 0; i < exact.size(); ++i) {
                if (!f.field.ok(i)) continue;
                if (f.field.x[i] < cx * 40 || f.field.x[i] >= cx * 40 + 40 ||
                    f.field.y[i] < cy * 40 || f.field.y[i] >= cy * 40 + 40)
                  continue;
                sum += comp ? f.field.u[i] - exact.u[i] : f.field.v[i] - exact.v[i];
                ++cnt;
              }
              if (cnt) std::printf(" %+6.0f", 1e4 * sum / cnt);
              else std::printf("      .");
            }
            std::printf("\n");
          }
        }
      }
      const dic::CrackLine& L = f.line_used;
      std::vector<dic::FieldFitJResult> fits;
      auto j_of = [&](const dic::DisplacementField& field, double x, double y, double s) {
        const dic::FrameJ r =
            dic::ComputeFrameJ(field, x, y, s, L.x1 - L.x0, L.y1 - L.y0, opt.tip.band_half_width_px,
                               kScale, kOffset, opt.j_integral);
        fits.push_back(r.fit);
        return r.status == dic::FrameJStatus::kOk ? 100 * (r.J_ff / J[k] - 1) : NAN;
      };
      const double true_s = std::hypot(tip_x[k] - L.x0, tip_y[k] - L.y0);
      const double e[4] = {j_of(f.field, f.tip.tip.x_px, f.tip.tip.y_px, f.tip.tip.s_px),
                           j_of(f.field, tip_x[k], tip_y[k], true_s),
                           j_of(exact, f.tip.tip.x_px, f.tip.tip.y_px, f.tip.tip.s_px),
                           j_of(exact, tip_x[k], tip_y[k], true_s)};
      if (std::getenv("BF_HYBRID")) {
        // The exact field with the DIC's values in one region only: which
        // region's DIC error moves the fit's J (true tip).
        const char* names[5] = {"|n|<30", "30<=|n|<60", "|n|>=60", "behind tip", "ahead of tip"};
        std::printf("  hybrid fit J err [%%]:");
        for (int region = 0; region < 5; ++region) {
          dic::DisplacementField h = exact;
          for (size_t i = 0; i < h.size(); ++i) {
            const double an = std::abs(h.y[i] - tip_y[k]);
            const bool in = region == 0   ? an < 30
                            : region == 1 ? an >= 30 && an < 60
                            : region == 2 ? an >= 60
                            : region == 3 ? h.x[i] < tip_x[k]
                                          : h.x[i] >= tip_x[k];
            if (in) h.u[i] = f.field.u[i], h.v[i] = f.field.v[i];
          }
          j_of(h, tip_x[k], tip_y[k], true_s);
          std::printf("  %s %+.2f", names[region], 100 * (fits.back().J / J[k] - 1));
        }
        std::printf("\n");
      }
      std::printf(
          "%5zu  %7.2f  %+8.2f  %+10.2f  %+12.2f  %+13.2f  %+13.2f   u, v RMS err %.4f %.4f px\n",
          k, zone_px * kScale * 1e3, f.tip.tip.x_px - tip_x[k], e[0], e[1], e[2], e[3],
          std::sqrt(du2 / ok), std::sqrt(dv2 / ok));
      for (int i = 0; i < 4; ++i) ss[i] += e[i] * e[i];
      std::printf("       fit J err [%%] (u [%%], z, check, status):");
      for (int i = 0; i < 4; ++i) {
        const dic::FieldFitJResult& q = fits[i];
        const double err = 100 * (q.J / J[k] - 1);
        fss[i] += err * err;
        zss[i] += std::pow(err / (100 * q.J_uncertainty / J[k]), 2);
        std::printf("  %+6.2f (%.2f %+.1f %+.2f %s)", err, 100 * q.J_uncertainty / J[k],
                    err / (100 * q.J_uncertainty / J[k]), 100 * (q.J_check / J[k] - 1),
                    dic::FieldFitJStatusName(q.status));
      }
      std::printf("\n         fit stat %.2f%% corr %.1f res %.3g um signal %.3g um pts %d\n",
                  100 * fits[0].J_statistical / J[k], fits[0].correlation_factor,
                  fits[0].residual_rms_m * 1e6, fits[0].signal_rms_m * 1e6, fits[0].points);
      ++n;
    }
    std::printf("RMS [%%] over %d frames:      %+10.2f  %+12.2f  %+13.2f  %+13.2f\n", n,
                std::sqrt(ss[0] / n), std::sqrt(ss[1] / n), std::sqrt(ss[2] / n),
                std::sqrt(ss[3] / n));
    std::printf("fit RMS [%%]:                  %+10.2f  %+12.2f  %+13.2f  %+13.2f\n",
                std::sqrt(fss[0] / n), std::sqrt(fss[1] / n), std::sqrt(fss[2] / n),
                std::sqrt(fss[3] / n));
    std::printf("fit RMS z:                    %+10.2f  %+12.2f  %+13.2f  %+13.2f\n",
                std::sqrt(zss[0] / n), std::sqrt(zss[1] / n), std::sqrt(zss[2] / n),
                std::sqrt(zss[3] / n));
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
