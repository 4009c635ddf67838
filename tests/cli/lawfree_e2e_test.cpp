// The law-free route through the product (issue 21), end to end:
//   bridgefit synth --bridged-field  (speckle frames of a bridged crack whose
//                                     faces carry a linear law, K_tip = K_tip,c)
//   bridgefit dic --scene --j-integral (J_ff and delta* per frame)
//   bridgefit lawfree                  (sigma(delta) from J_ff(delta*))
// against the generator's truth (images/truth.csv: J_ff, delta_root per
// frame) and the scene's law.
//
// What holds and is asserted (measured on this set-up, 16 frames 400 x 320
// px at 0.1 mm/px, subset 31 px, step 5 px; docs/LAW_FREE.md):
//  - every frame but the reference has J_ff and delta*: from the opening
//    profile, or where the zone is shorter than the profile's stretch (2
//    grid points) the near-tip opening sqrt(32 r J_ff / (pi E')), within 2
//    of its stated u (measured 26.9 um for 26.9 here; dic/frame_j.hpp);
//  - delta* per frame within 3 % (+ 1 um) of the generator's root opening
//    where the zone is at least 3 mm, within 10 % below (the stretch reaches
//    8 points behind the root and 0.35 of the zone ahead of it, 2 points at
//    least, dic/frame_j.hpp; measured -1.5 .. +0.2 % here), exactly 0 at the
//    onset frame;
//  - J_ff per frame within 8 % of the generator's (measured 0.1-3.8 %: the
//    domain integral on DIC gradients scatters a few percent), and the
//    field-wide fit's J_ff (dic/j_fit.hpp, what lawfree uses) within 3 %
//    (measured -0.8 .. +1.2 %, RMS 0.5 %), its uncertainty holding the
//    error within 2 u on all but at most 3 frames (measured 15 of 15);
//  - the onset of growth at frame 1, the delta* = 0 frame (not a kink in
//    J_ff(delta*), which a drift of the J scatter can fake);
//  - J_tip,c within 5 %;
//  - the mean sigma over the covered openings, W(delta_max) / delta_max,
//    within 10 % of the law's.
// What does not hold on every run and is only printed: sigma(delta)
// pointwise within 10 % over the covered range (0 to the largest delta*, 41
// nodes): worst 12.6 % here (2026-12-04; the end of the range, where the
// band is +-45 %); through `bridgefit lawfree` within 10 % on 8 of 14 runs
// of 16 frames and 5 of 8 of 48 frames, the band holding the law on all
// but one (docs/LAW_FREE.md "Near-tip openings and flagged frames"). The
// misses sit at the ends of the range, where J errors that drift together
// over the last frames tilt the derivative.
// Asserted too: the data stop far before steady state, so J_B and delta_c
// are lower bounds below the truth (the J route used to take the J scatter
// for a plateau and print J_B about 100 J/m^2 as a value; the plateau rule
// now needs flatness established, docs/LAW_FREE.md).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../cli/cli_helpers.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

namespace bridgefit::pipeline {
namespace {
namespace fs = std::filesystem;
using bridgefit::testing::RunCli;

constexpr double kSigmaC = 1e6, kDeltaC = 2e-3, kJtip = 200;  // the scene's law
double Sigma(double d) { return d < kDeltaC ? kSigmaC * (1 - d / kDeltaC) : 0.0; }
double Work(double d) { return kSigmaC * (d - d * d / (2 * kDeltaC)); }

TEST(LawFreeEndToEnd, SynthDicLawFreeRecoversTheLinearLaw) {
  const fs::path dir = fs::temp_directory_path() / ("bf_lawfree_e2e_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "scene.toml") << R"([specimen]
type = "ct"
width = "100 mm"
height = "120 mm"
thickness = "12.7 mm"
notch = "30 mm"
plane = "stress"
[material]
E = "3 GPa"
nu = 0.3
[fracture]
J_tip_c = "200 J/m^2"
[bridging]
law = "linear"
sigma_c = "1 MPa"
J_B = "1000 J/m^2"
[run]
max_crack_length = "45 mm"
)";
  const std::string d = "'" + dir.string() + "'";
  auto run = [](const std::string& args) {
    const auto r = RunCli(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    return r;
  };
  run("synth " + d + "/scene.toml --out " + d + " --frames 16 --bridged-field --image-width 400 "
      "--image-height 320 --scale 0.1mm --image-x0 15mm --quiet");
  run("dic " + d + "/images --crack-line 0,160,399,160 --scale 0.1mm/px --offset 15mm --scene " + d +
      "/scene.toml --j-integral --out " + d + "/dic.h5 --csv " + d + "/dic.csv --quiet");
  const auto lawfree = run("lawfree " + d + "/dic.h5 --out " + d + "/lawfree.h5");
  std::printf("%s", lawfree.out.c_str());

  // Per frame against the generator.
  const io::CsvTable truth = io::ReadCsvTable(dir / "images" / "truth.csv");
  const std::vector<double> true_j = truth.columns[truth.Find("J_ff")];
  const std::vector<double> true_delta = truth.ColumnSi("delta_root", Dimension::Length());
  const DicJSeries dic = ReadDicJSeries(dir / "dic.h5");
  ASSERT_EQ(dic.image.size(), true_j.size());
  int fit_within_2u = 0, fit_frames = 0;
  for (size_t k = 1; k < dic.image.size(); ++k) {
    ASSERT_EQ(dic.J_status[k], "ok") << "frame " << k;
    ASSERT_EQ(dic.delta_star_status[k], "ok") << "frame " << k;
    if (dic.delta_star_method[k] == "near_tip") {
      // The tip past the root by less than the profile's stretch (2 grid
      // points, 1 mm): the near-tip opening, a number with its uncertainty.
      std::printf("frame %2zu: near-tip delta* %.4f +- %.4f mm (true %.4f mm)\n", k,
                  dic.delta_star[k] * 1e3, dic.delta_star_uncertainty[k] * 1e3, true_delta[k] * 1e3);
      EXPECT_LE(std::abs(dic.delta_star[k] - true_delta[k]), 2 * dic.delta_star_uncertainty[k]);
      EXPECT_LT(truth.ColumnSi("crack_length", Dimension::Length())[k] - 30e-3, 2.5e-3);
    }
    const double j_err = dic.J_ff[k] / true_j[k] - 1;
    std::printf("frame %2zu: J_ff %7.2f (true %7.2f, %+5.1f %%, spread %4.1f %%), delta* %.4f mm "
                "(true %.4f mm)\n",
                k, dic.J_ff[k], true_j[k], 100 * j_err, dic.J_ff_spread_percent[k],
                dic.delta_star[k] * 1e3, true_delta[k] * 1e3);
    EXPECT_LT(std::abs(j_err), 0.08) << "frame " << k;
    // The field-wide fit's J_ff, the one lawfree uses (dic/j_fit.hpp):
    // measured -0.8 .. +1.2 % here (RMS 0.5 %), -2.4 .. +1.9 % over six
    // runs (docs/LAW_FREE.md "The field-wide fit"); its uncertainty (the
    // leave-tile-out residuals) holds the error within 2 u on 14 of 14
    // frames here, 133 of 135 over nine runs ("What the residuals miss").
    ASSERT_EQ(dic.J_fit_status[k], "ok") << "frame " << k;
    const double fit_err = dic.J_ff_fit[k] / true_j[k] - 1;
    std::printf("          J_ff fit %7.2f (%+5.2f %%, u %.2f %%)\n", dic.J_ff_fit[k], 100 * fit_err,
                100 * dic.J_ff_fit_uncertainty[k] / dic.J_ff_fit[k]);
    EXPECT_LT(std::abs(fit_err), 0.03) << "frame " << k;
    fit_within_2u += std::abs(dic.J_ff_fit[k] - true_j[k]) <= 2 * dic.J_ff_fit_uncertainty[k];
    ++fit_frames;
    // The stretch ahead of the root is 0.35 of the zone, 2 grid points at
    // least (the near-tip curvature read it 5-8 % low on 2.5-5 mm zones
    // when it reached 0.9 of the zone); on zones under 3 mm the 2 points
    // are most of it (measured -1.0 % here, -6.4 % on another run).
    const double zone = truth.ColumnSi("crack_length", Dimension::Length())[k] - 30e-3;
    const double tolerance = zone < 3e-3 ? 0.10 : 0.03;
    EXPECT_NEAR(dic.delta_star[k], true_delta[k], tolerance * true_delta[k] + 1e-6)
        << "frame " << k << ", zone " << zone * 1e3 << " mm";
  }

  EXPECT_GE(fit_within_2u, fit_frames - 1) << "of " << fit_frames;

  // Issue 18 on a bridged crack: every frame's length within 2 u of the
  // truth or flagged. The traction-free Williams tip lies 3-6 px behind
  // here (-0.27 .. -0.57 mm from frame 5 on); before the closing-traction
  // share joined the uncertainty it was stated as 0.144 mm (z to -3.9).
  {
    std::ifstream csv(dir / "dic.csv");
    auto split = [](const std::string& text) {
      std::vector<std::string> cell;
      std::stringstream ss(text);
      for (std::string c; std::getline(ss, c, ',');) {
        const auto b = c.find_first_not_of(' '), e = c.find_last_not_of(' ');
        cell.push_back(b == std::string::npos ? "" : c.substr(b, e - b + 1));
      }
      return cell;
    };
    std::string line;
    std::getline(csv, line);
    const std::vector<std::string> header = split(line);
    auto column = [&](const std::string& name) {
      const auto it = std::find(header.begin(), header.end(), name);
      EXPECT_NE(it, header.end()) << name;
      return static_cast<std::size_t>(it - header.begin());
    };
    const std::size_t raw = column("crack_length_raw [mm]"), unc = column("uncertainty [mm]"),
                      flags = column("flags");
    const std::vector<double> true_a = truth.ColumnSi("crack_length", Dimension::Length());
    int k = 0, covered = 0, frames = 0;
    while (std::getline(csv, line)) {
      const std::vector<std::string> cell = split(line);
      if (k > 0 && cell.size() > flags && !cell[raw].empty()) {
        const double a = std::stod(cell[raw]) * 1e-3, u = std::stod(cell[unc]) * 1e-3;
        const bool flagged = !cell[flags].empty();
        const bool ok = std::abs(a - true_a[k]) <= 2 * u || flagged;
        covered += ok;
        ++frames;
        EXPECT_TRUE(ok) << "frame " << k << ": a " << a * 1e3 << " mm, truth " << true_a[k] * 1e3
                        << " mm, u " << u * 1e3 << " mm";
      }
      ++k;
    }
    EXPECT_EQ(frames, 15);
    std::printf("crack lengths within 2 u of the truth or flagged: %d of %d frames\n", covered, frames);
  }

  // The law.
  const LawFreeRun out = ReadLawFreeH5(dir / "lawfree.h5");
  ASSERT_TRUE(out.far_field.has_value());
  const laws::LawFreeResult& r = *out.far_field;
  EXPECT_NEAR(r.J_tip_c, kJtip, 0.05 * kJtip);
  // The onset of growth is frame 1 (the tip at the notch root: dic writes
  // delta* = 0), not a kink in J_ff(delta*) that the J scatter can fake.
  EXPECT_FALSE(r.onset_detected);
  EXPECT_EQ(r.onset_index, 0);
  EXPECT_NE(lawfree.out.find("onset of growth: frame 1 ("), std::string::npos) << lawfree.out;
  // Pointwise over the covered range (the grid runs from the onset frame's
  // opening, 0, to the largest measured delta*): printed, not asserted
  // (within 10 % on 5 of 14 runs measured, docs/LAW_FREE.md "What the
  // residuals miss"). The band holds the law at every node: asserted
  // (13 of those 14 runs; one missed 3 of 41 nodes at the range's end, held
  // since the end windows of session 49, "The range's ends").
  double worst = 0;
  int misses = 0;
  for (size_t j = 0; j < r.delta.size(); ++j) {
    const double truth_j = Sigma(r.delta[j]);
    const double err = r.sigma[j] / truth_j - 1;
    worst = std::max(worst, std::abs(err));
    if (truth_j < r.sigma_lower[j] || truth_j > r.sigma_upper[j]) ++misses;
  }
  const double delta_max = r.delta.back();
  // Mean sigma over [0, delta_max]: the fitted rise of J_ff (the grid's
  // trapezoid area of sigma) against the law's W(delta_max).
  double area = 0;
  for (size_t j = 1; j < r.delta.size(); ++j)
    area += 0.5 * (r.sigma[j] + r.sigma[j - 1]) * (r.delta[j] - r.delta[j - 1]);
  const double mean_err = area / Work(delta_max) - 1;
  std::printf("law-free J route: J_tip,c %.1f J/m^2 (true %.0f), openings to %.4f mm, mean sigma "
              "error %+.1f %%, worst pointwise sigma error %.1f %% (%zu nodes, not asserted), "
              "band misses %d\n",
              r.J_tip_c, kJtip, delta_max * 1e3, 100 * mean_err, 100 * worst, r.delta.size(),
              misses);
  EXPECT_LT(std::abs(mean_err), 0.10);
  EXPECT_EQ(misses, 0) << "the 95 % band misses the law at " << misses << " of " << r.delta.size()
                       << " nodes";
  // The data stop far before steady state (delta* to about 0.1 mm of
  // delta_c 2 mm): J_B and delta_c are lower bounds below the truth, never
  // values (the plateau rule's equivalence test: the J scatter used to pass
  // for a plateau, J_B "100 J/m^2" as a value).
  const double kJB = 1000.0, kDeltaC = 2e-3;
  EXPECT_FALSE(r.identified) << r.Summary();
  EXPECT_FALSE(r.J_B.identified);
  EXPECT_LE(r.J_B.value, kJB);
  EXPECT_FALSE(r.delta_c.identified);
  EXPECT_LE(r.delta_c.value, kDeltaC);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit::pipeline
