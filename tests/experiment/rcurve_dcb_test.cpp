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

// Compliance calibration: a single power law C = k a^n cannot follow
// (a + Delta)^3 over a 2.7x range of crack length, so it is high early and
// low late. Measured: mean |err| 3-4%, max 5.5% (DCB-01) and 6.3% (DCB-02);
// the test pins the mean within 5% and states the maximum (docs/RCURVE_METHODS.md).
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

INSTANTIATE_TEST_SUITE_P(Specimens, RealDcb,
                         ::testing::Values("DCB-01_Toughness.csv", "DCB-02_Toughness.csv"));

}  // namespace
}  // namespace bridgefit::experiment
