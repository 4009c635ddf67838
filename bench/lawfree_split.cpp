// Where the law-free J route's pointwise sigma error comes from
// (docs/LAW_FREE.md). On a `synth --bridged-field` run followed by
// `dic --j-integral` (DIR/images/truth.csv, DIR/dic.h5), the same frames
// go through the same derivative (laws::LawFromFarFieldJ, default options,
// the pipeline's J uncertainties) four times:
//   measured J_ff, measured delta*   (what `bridgefit lawfree` does)
//   true J_ff,     measured delta*   (the delta* error alone)
//   measured J_ff, true delta_root   (the J error alone)
//   true J_ff,     true delta_root   (the derivative's own error)
// and each is compared with the scene's law node by node.
//   lawfree_split DIR SCENE
// Environment: BF_J_SOURCE=domains (the domains' J), BF_RULE=ubre|discrepancy
// (the penalty rule; GCV otherwise), BF_GCV_GAMMA (GCV's dof inflation).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law_free.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

namespace fs = std::filesystem;
using namespace bridgefit;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: lawfree_split DIR SCENE\n");
    return 2;
  }
  try {
    const fs::path dir = argv[1];
    const Scene scene = io::ReadSceneFile(argv[2]);
    const laws::BridgingLaw law = scene.bridging->Law();
    const double j_tip = scene.fracture->J_tip_c;
    const io::CsvTable truth = io::ReadCsvTable(dir / "images" / "truth.csv");
    const std::vector<double> true_j = truth.columns[truth.Find("J_ff")];
    const std::vector<double> true_d = truth.ColumnSi("delta_root", Dimension::Length());
    const pipeline::DicJSeries s = pipeline::ReadDicJSeries(dir / "dic.h5");
    pipeline::LawFreeRequest request;  // the pipeline's uncertainty floors and J source
    if (const char* e = std::getenv("BF_J_SOURCE"); e && std::string(e) == "domains")
      request.j_source = pipeline::LawFreeRequest::JSource::kDomains;
    std::printf(
        "frame  J_ff meas/true-1 [%%]  u [%%]  delta* meas [um]  true [um]  "
        "err [%%]  true J - J_tip - W(true delta) [J/m^2]  delta* method  flags\n");
    // Per frame, as the pipeline takes J_ff (the field fit's where ok).
    for (size_t k = 0; k < s.image.size(); ++k) {
      if (s.J_status[k] != "ok" || s.delta_star_status[k] != "ok") continue;
      const bool fit = request.j_source == pipeline::LawFreeRequest::JSource::kFieldFit &&
                       s.J_fit_status[k] == "ok";
      const double spread = std::isfinite(s.J_ff_spread_percent[k]) ? s.J_ff_spread_percent[k] : 0;
      const double j = fit ? s.J_ff_fit[k] : s.J_ff[k];
      const double u = fit ? std::max(s.J_ff_fit_uncertainty[k], request.j_fit_relative_floor * j)
                           : std::max(0.5 * spread / 100, request.j_relative_floor) * j;
      std::printf("%5zu  %+8.2f  %8.2f  %10.3f  %10.3f  %+7.2f  %+8.3f  %s %s\n", k,
                  100 * (j / true_j[k] - 1), 100 * u / j, s.delta_star[k] * 1e6, true_d[k] * 1e6,
                  true_d[k] > 0 ? 100 * (s.delta_star[k] / true_d[k] - 1) : 0.0,
                  true_j[k] - j_tip - law.Work(true_d[k]), s.delta_star_method[k].c_str(),
                  s.flags[k].c_str());
    }
    // The samples as `bridgefit lawfree` assembles them
    // (pipeline::FarFieldJSamplesOf), from the series with the generator's J
    // and/or delta_root swapped in: one rule for all four.
    auto samples = [&](bool use_true_j, bool use_true_d) {
      pipeline::DicJSeries c = s;
      for (size_t k = 0; k < c.image.size(); ++k) {
        if (use_true_j && std::isfinite(true_j[k])) c.J_ff[k] = c.J_ff_fit[k] = true_j[k];
        if (use_true_d && std::isfinite(true_d[k])) c.delta_star[k] = true_d[k];
      }
      std::vector<std::string> notes;
      return pipeline::FarFieldJSamplesOf(c, request, notes);
    };
    const laws::FarFieldJSamples mm = samples(false, false), tm = samples(true, false),
                                 mt = samples(false, true), tt = samples(true, true);
    auto report = [&](const char* name, const laws::FarFieldJSamples& in) {
      laws::LawFreeResult r;
      try {
        laws::LawFreeOptions o;
        if (const char* e = std::getenv("BF_RULE"))
          o.penalty_rule = std::string(e) == "ubre" ? laws::PenaltyRule::kUnbiasedRisk
                           : std::string(e) == "discrepancy" ? laws::PenaltyRule::kDiscrepancy
                                                             : laws::PenaltyRule::kGeneralisedCrossValidation;
        if (const char* e = std::getenv("BF_GCV_GAMMA")) o.gcv_gamma = std::atof(e);
        r = laws::LawFromFarFieldJ(in, o);
      } catch (const Error& e) {
        std::printf("%-26s %s\n", name, e.what());
        return;
      }
      double worst = 0, rms = 0, worst_in = 0, worst_cov = 0;
      int n_in = 0, n_cov = 0, misses = 0;
      const double dmax = r.delta.back();
      std::string row;
      for (size_t j = 0; j < r.delta.size(); ++j) {
        const double t = law.Traction(r.delta[j]);
        const double e = r.sigma[j] / t - 1;
        worst = std::max(worst, std::abs(e));
        rms += e * e;
        if (r.delta[j] >= 0.1 * dmax && r.delta[j] <= 0.9 * dmax) {
          worst_in = std::max(worst_in, std::abs(e)), ++n_in;
        }
        const double half = 0.5 * (r.sigma_upper[j] - r.sigma_lower[j]);
        if (r.resolved[j]) worst_cov = std::max(worst_cov, std::abs(e)), ++n_cov;
        if (t < r.sigma_lower[j] || t > r.sigma_upper[j]) ++misses;
        if (j % 5 == 0)
          row += fmt::format(" {:.0f}um:{:+.1f}%(+-{:.1f})", r.delta[j] * 1e6, 100 * e,
                             100 * half / t);
      }
      std::printf(
          "%-26s onset %d%s J_tip,c %6.1f  lambda 10^%.1f  dof %.1f  s %.2f  worst %5.1f %%  rms "
          "%4.1f "
          "%%  worst 10-90 %% of range %5.1f %%  worst where resolved (%d nodes) %5.1f "
          "%%  band misses %d/%zu\n   %s\n",
          name, r.onset_index, r.onset_detected ? "(found)" : "", r.J_tip_c,
          r.penalty_log10_relative, r.effective_dof, r.noise_scale, 100 * worst,
          100 * std::sqrt(rms / r.delta.size()), 100 * worst_in, n_cov, 100 * worst_cov, misses,
          r.delta.size(), row.c_str());
    };
    report("measured J, measured d*", mm);
    report("true J, measured d*", tm);
    report("measured J, true d", mt);
    report("true J, true d", tt);
    // The same measured samples with one uncertainty for all (the RMS of
    // the stated ones): are the spread-based weights worth their noise?
    laws::FarFieldJSamples flat = mm;
    double ms = 0;
    for (double u : mm.uncertainty) ms += u * u / mm.uncertainty.size();
    std::fill(flat.uncertainty.begin(), flat.uncertainty.end(), std::sqrt(ms));
    report("measured, equal weights", flat);
    flat.onset_index.reset();
    report("  ... onset detected", flat);
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
