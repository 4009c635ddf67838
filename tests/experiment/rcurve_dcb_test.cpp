// The real DCB tests (tests/data/experiment, PROVENANCE.md): MBT and
// compliance calibration against the data authors' G_I column, and the noise
// test of the issue on real data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::experiment {
namespace {

struct DcbData {
  ExperimentRecord record;          // SI
  std::vector<double> authors_G;    // J/m^2 per record row (NaN where missing)
};

// Minimal reader for the five-column files (the product reads them with
// io::ReadRecordCsv; this test must not depend on the io module).
DcbData ReadDcb(const std::string& name) {
  const std::string path = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/experiment/" + name;
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  DcbData data;
  data.record.source = path;
  std::string line;
  std::getline(in, line);  // Time,Disp,Force,CrackExt,G_I
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(cells, cell, ',')) v.push_back(cell.empty() ? NAN : std::strtod(cell.c_str(), nullptr));
    if (v.size() < 5 || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3])) continue;
    data.record.time.push_back(v[0]);
    data.record.displacement.push_back(v[1] * 1e-3);  // mm
    data.record.load.push_back(v[2]);                 // N
    data.record.crack_length.push_back(v[3] * 1e-3);  // mm
    data.authors_G.push_back(v[4] * 1e3);             // N/mm -> J/m^2
  }
  return data;
}

RCurveOptions PaperOptions(RMethod method) {
  RCurveOptions o;
  o.method = method;
  o.specimen.type = SpecimenType::kDCB;
  o.specimen.width = 25e-3;
  o.specimen.height = 2.7e-3;
  o.specimen.length = 123e-3;
  o.material.E = 19.3e9;
  return o;
}

struct Agreement {
  int points = 0;
  int within_5_percent = 0;
  double max_abs = 0.0;
  double mean_abs = 0.0;
  double mean = 0.0;
};

Agreement Compare(const RCurveResult& r, const DcbData& data) {
  Agreement s;
  for (std::size_t i = 0; i < r.curve.size(); ++i) {
    const double ref = data.authors_G[r.rows[i]];
    if (!(ref > 0)) continue;
    const double e = r.curve.R[i] / ref - 1.0;
    ++s.points;
    s.within_5_percent += std::abs(e) <= 0.05;
    s.max_abs = std::max(s.max_abs, std::abs(e));
    s.mean_abs += std::abs(e);
    s.mean += e;
  }
  s.mean_abs /= std::max(1, s.points);
  s.mean /= std::max(1, s.points);
  return s;
}

class RealDcb : public ::testing::TestWithParam<const char*> {};

// MBT reproduces the authors' G_I at every propagation point within 5%
// (measured: 1.5% for both specimens, a constant offset of -1.4%).
TEST_P(RealDcb, MbtReproducesAuthorsGWithin5Percent) {
  const DcbData data = ReadDcb(GetParam());
  const RCurveResult r = ComputeRCurve(data.record, PaperOptions(RMethod::kMbt));
  const Agreement s = Compare(r, data);
  std::printf("%s MBT: %d points, Delta = %.3f mm, max |err| %.2f%%, mean err %.2f%%\n",
              GetParam(), s.points, r.figures.at("mbt_delta_m") * 1e3, 100 * s.max_abs,
              100 * s.mean);
  EXPECT_GT(s.points, 300);
  EXPECT_EQ(s.within_5_percent, s.points);
}

// Compliance calibration (D5528: one power law C = k a^n over the
// propagation rows). The per-point criterion (every point within 5%)
// is NOT met: one power law cannot follow (a + Delta)^3 over a 2.7-3.3x range
// of crack length (Delta = 6.7-7.1 mm), so CC is high early and low late
// (ComplianceCalibration.SinglePowerLawMissesBeamComplianceOverLongRange shows
// the same on exact beam data); the authors' column is MBT x 1/0.986, which
// adds -1.4%. Measured: within 5% at 274/338 (DCB-01) and 234/414 (DCB-02)
// points, mean |err| 3.3% and 4.2%, max 5.6% and 6.4%. The test pins the
// mean within 5% and the maximum below 7% (docs/RCURVE_METHODS.md).
TEST_P(RealDcb, ComplianceCalibrationReproducesAuthorsGOnAverage) {
  const DcbData data = ReadDcb(GetParam());
  const RCurveResult r = ComputeRCurve(data.record, PaperOptions(RMethod::kComplianceCalibration));
  const Agreement s = Compare(r, data);
  std::printf("%s CC: %d points, n = %.4f, max |err| %.2f%%, mean |err| %.2f%%, within 5%%: %d\n",
              GetParam(), s.points, r.figures.at("cc_n"), 100 * s.max_abs, 100 * s.mean_abs,
              s.within_5_percent);
  EXPECT_GT(s.points, 300);
  EXPECT_LT(s.mean_abs, 0.05);
  EXPECT_LT(s.max_abs, 0.07);
}

// D5528's large-displacement (F) and load-block (N) corrections with t = L' = 0
// (the fixture is not described; d/a reaches 0.30-0.35, F >= 0.963, N >= 0.969).
// They do not rescue CC's per-point agreement: within 5% at 310/338 and
// 274/414 points, max 5.4% and 6.7% (the authors did not apply them: their
// column is a constant multiple of plain MBT). MBT with F/N stays within 5%
// everywhere (max 1.4%).
TEST_P(RealDcb, LargeDisplacementCorrectionsOnAuthorsG) {
  const DcbData data = ReadDcb(GetParam());
  for (RMethod method : {RMethod::kComplianceCalibration, RMethod::kMbt}) {
    RCurveOptions o = PaperOptions(method);
    o.large_displacement_correction = true;
    const RCurveResult c = ComputeRCurve(data.record, o);
    const Agreement f = Compare(c, data);
    std::printf("%s %s F/N: %d points, max |err| %.2f%%, mean err %.2f%%, mean |err| %.2f%%, "
                "within 5%%: %d, F >= %.4f, N >= %.4f, %s = %.4f\n",
                GetParam(), RMethodName(method), f.points, 100 * f.max_abs, 100 * f.mean,
                100 * f.mean_abs, f.within_5_percent, c.figures.at("d5528_F_min"),
                c.figures.at("d5528_N_min"), method == RMethod::kMbt ? "Delta [mm]" : "n",
                method == RMethod::kMbt ? 1e3 * c.figures.at("mbt_delta_m") : c.figures.at("cc_n"));
    EXPECT_GT(f.points, 300);
    EXPECT_LT(c.figures.at("d5528_F_min"), 0.98);  // the arms do rotate noticeably
    if (method == RMethod::kMbt) {
      EXPECT_EQ(f.within_5_percent, f.points);
    } else {
      EXPECT_LT(f.mean_abs, 0.05);
      EXPECT_LT(f.max_abs, 0.07);
    }
  }
}

// Noise of the issue: 1% on the load, 0.5 mm on the crack length. The change
// of R stays below the reported (k = 2) uncertainty in >= 90% of the points.
TEST_P(RealDcb, NoiseChangesRLessThanReportedUncertainty) {
  const DcbData data = ReadDcb(GetParam());
  ExperimentRecord noisy = data.record;
  std::mt19937 rng(99);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    noisy.load[i] = std::max(0.0, noisy.load[i] * (1.0 + 0.01 * unit(rng)));
    noisy.crack_length[i] += 0.5e-3 * unit(rng);
  }
  for (RMethod method : {RMethod::kMbt, RMethod::kComplianceCalibration}) {
    const RCurveResult clean = ComputeRCurve(data.record, PaperOptions(method));
    const RCurveResult r = ComputeRCurve(noisy, PaperOptions(method));
    int compared = 0, inside = 0;
    for (std::size_t i = 0; i < r.curve.size(); ++i) {
      const auto it = std::find(clean.rows.begin(), clean.rows.end(), r.rows[i]);
      if (it == clean.rows.end()) continue;
      const double R0 = clean.curve.R[it - clean.rows.begin()];
      ++compared;
      inside += std::abs(r.curve.R[i] - R0) < r.curve.R_uncertainty[i];
    }
    std::vector<double> rel;
    for (std::size_t i = 0; i < r.curve.size(); ++i) rel.push_back(r.curve.R_uncertainty[i] / r.curve.R[i]);
    std::sort(rel.begin(), rel.end());
    std::printf("%s %s noise: %d of %d points inside, median U/R %.3f, sigma_a %.3f mm\n",
                GetParam(), RMethodName(method), inside, compared, rel[rel.size() / 2],
                r.crack_length_noise * 1e3);
    EXPECT_GT(compared, 250);
    EXPECT_GE(inside, 0.9 * compared) << RMethodName(method);
  }
}

// The energy method on the visually tracked crack (issue 15): its increment
// comes from the readings' own scatter about a smooth monotone fit, not from
// the compliance law's misfit, so it gives >= 10 points over the propagation
// range, on average within 5% of MBT over the same rows (each energy point
// against the mean MBT R of the rows of its increment).
TEST_P(RealDcb, EnergyMethodGivesTenPointsNearMbtOnAverage) {
  const DcbData data = ReadDcb(GetParam());
  const RCurveResult e = ComputeRCurve(data.record, PaperOptions(RMethod::kEnergy));
  const RCurveResult m = ComputeRCurve(data.record, PaperOptions(RMethod::kMbt));
  double sum = 0.0, sum_abs = 0.0;
  int compared = 0, covered = 0;
  for (std::size_t i = 0; i < e.curve.size(); ++i) {
    const int first = i == 0 ? e.initiation.visual_row : e.rows[i - 1];
    double mbt = 0.0;
    int n = 0;
    for (std::size_t k = 0; k < m.curve.size(); ++k)
      if (m.rows[k] > first && m.rows[k] <= e.rows[i]) mbt += m.curve.R[k], ++n;
    if (n == 0) continue;
    const double rel = e.curve.R[i] / (mbt / n) - 1.0;
    std::printf("  a = %.2f mm: R_energy %.0f, MBT %.0f J/m^2 (%+.1f%%), U %.0f\n",
                e.curve.crack_length[i] * 1e3, e.curve.R[i], mbt / n, 100 * rel, e.curve.R_uncertainty[i]);
    sum += rel, sum_abs += std::abs(rel), ++compared;
    covered += std::abs(e.curve.R[i] - mbt / n) <= e.curve.R_uncertainty[i];
  }
  std::printf("%s energy: %zu points, increment %.2f mm, mean vs MBT %+.2f%%, mean |diff| %.1f%%, "
              "|R_energy - MBT| <= U at %d\n",
              GetParam(), e.curve.size(), 1e3 * e.figures.at("energy_min_increment_m"),
              100 * sum / compared, 100 * sum_abs / compared, covered);
  EXPECT_GE(e.curve.size(), 10u);
  EXPECT_EQ(compared, static_cast<int>(e.curve.size()));
  EXPECT_LT(std::abs(sum / compared), 0.05);
}

// A given compliance calibration replaces the fitted one (the fit reduces
// the model's own record with the data's constants): with the record's own
// Delta given, every R is the fitted reduction's; with Delta 1 mm larger,
// every R is 3 P d / (2 b (a + |Delta|)) with that Delta, i.e. the fitted R
// times (a + |Delta|) / (a + |Delta| + 1 mm); the same for cc's n.
TEST_P(RealDcb, AGivenComplianceCalibrationIsUsedAsGiven) {
  const DcbData data = ReadDcb(GetParam());
  const RCurveResult fitted = ComputeRCurve(data.record, PaperOptions(RMethod::kMbt));
  const double delta = fitted.figures.at("mbt_delta_m");
  RCurveOptions same = PaperOptions(RMethod::kMbt), shifted = same;
  same.given_mbt_delta = delta;
  shifted.given_mbt_delta = delta + (delta < 0 ? -1e-3 : 1e-3);
  const RCurveResult r_same = ComputeRCurve(data.record, same);
  const RCurveResult r_shifted = ComputeRCurve(data.record, shifted);
  ASSERT_EQ(r_same.curve.size(), fitted.curve.size());
  ASSERT_EQ(r_shifted.curve.size(), fitted.curve.size());
  for (std::size_t i = 0; i < fitted.curve.size(); ++i) {
    const double a = fitted.curve.crack_length[i];
    EXPECT_DOUBLE_EQ(r_same.curve.R[i], fitted.curve.R[i]) << i;
    EXPECT_NEAR(r_shifted.curve.R[i] / fitted.curve.R[i],
                (a + std::abs(delta)) / (a + std::abs(delta) + 1e-3), 1e-12)
        << i;
  }
  EXPECT_DOUBLE_EQ(r_shifted.figures.at("mbt_delta_m"), shifted.given_mbt_delta);
  EXPECT_TRUE(std::any_of(r_shifted.notes.begin(), r_shifted.notes.end(), [](const std::string& n) {
    return n.find("compliance calibration given") != std::string::npos;
  }));

  const RCurveResult cc = ComputeRCurve(data.record, PaperOptions(RMethod::kComplianceCalibration));
  RCurveOptions cc_given = PaperOptions(RMethod::kComplianceCalibration);
  cc_given.given_cc_exponent = 1.1 * cc.figures.at("cc_n");
  const RCurveResult r_cc = ComputeRCurve(data.record, cc_given);
  ASSERT_EQ(r_cc.curve.size(), cc.curve.size());
  for (std::size_t i = 0; i < cc.curve.size(); ++i)
    EXPECT_NEAR(r_cc.curve.R[i] / cc.curve.R[i], 1.1, 1e-12) << i;

  RCurveOptions bad = PaperOptions(RMethod::kMbt);
  bad.given_cc_exponent = -1.0;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("given compliance calibration"), std::string::npos) << why;
}

INSTANTIATE_TEST_SUITE_P(Specimens, RealDcb,
                         ::testing::Values("DCB-01_Toughness.csv", "DCB-02_Toughness.csv"));

}  // namespace
}  // namespace bridgefit::experiment
