// Fault injection through the fits (issue 15): on the two real DCB records
// (tests/data/experiment, PROVENANCE.md), each fault of the issue's list is
// added and the documented fit routes run as library calls (pipeline::RunFit,
// no subprocess):
//   README chain   rcurve --method mbt, then fit of that R curve
//   docs/FIT.md    fit RECORD --fit-to load-displacement --calibrate-compliance=crack
//                  (in-process energy R curve for the start, the cleaning's
//                  envelope rows as the load data)
// Oracles: the clean record's fits, made with the same options. The faults
// leave every R point within 1% (faults_test.cpp) and take few rows out of
// the load data, so the fitted curves must stay close to the clean ones:
// the model R of the R-curve fit at the clean data's crack lengths, and the
// model load of the load fit at the clean rows' displacements.
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "record_faults.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace bridgefit::pipeline {
namespace {

using testing::NamedFault;
using testing::RecordFaults;

struct DcbCase {
  std::string file, scene;
};
const DcbCase kCases[] = {{"DCB-01_Toughness.csv", "scene.toml"},
                          {"DCB-02_Toughness.csv", "scene_dcb02.toml"}};

ExperimentRecord ReadDcb(const std::string& file) {
  io::RecordColumns columns;
  io::ApplyColumnMapping("time=Time,displacement=Disp,load=Force,crack_length=CrackExt", columns);
  io::ApplyUnitMapping("time=s,displacement=mm,load=N,crack_length=mm", columns);
  return io::ReadRecordCsv(std::string(BRIDGEFIT_TEST_DATA_DIR) + "/experiment/" + file, columns);
}

// `model`: the analytic (small-scale bridging) model for the R-curve routes
// (the faults act on the data, not on the model; this keeps a fit under a
// second), the reduced model at the documented element size for the load fit
// (the compliance calibration needs it). One start, no profiles: the clean and
// the faulted record get the same options, so the comparison is like with like.
FitRequest BaseRequest(const DcbCase& c, ModelChoice model) {
  FitRequest request;
  request.scene_path = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/dcb_composite/" + c.scene;
  request.scene = io::ReadSceneFile(request.scene_path);
  request.model = model;
  request.law = laws::LawFamily::kLinear;
  request.resolution = 0.6e-3;  // the documented commands' element size
  request.fit.profile_likelihood = false;
  request.fit.starts = 1;
  request.fit.threads = 1;
  return request;
}

// The README chain's R curve (rcurve --method mbt) of `record`.
experiment::RCurveResult Mbt(const FitRequest& base, const ExperimentRecord& record) {
  experiment::RCurveOptions o;
  o.method = experiment::RMethod::kMbt;
  o.specimen = base.scene.specimen;
  o.material = base.scene.material;
  return experiment::ComputeRCurve(record, o);
}

FitRun FitOfRCurve(const FitRequest& base, const ExperimentRecord& record) {
  FitRequest request = base;
  const experiment::RCurveResult mbt = Mbt(base, record);
  request.rcurve = mbt.curve;
  request.record = record;
  request.record_initial_compliance = mbt.initiation.initial_compliance;
  return RunFit(request);
}

FitRun LoadFit(const FitRequest& base, const ExperimentRecord& record) {
  FitRequest request = base;
  request.record = record;
  request.target = inverse::FitTarget::kLoad;
  request.calibration = inverse::ComplianceCalibrationMode::kAlongCrack;
  return RunFit(request);
}

// Linear interpolation of y(x) (x increasing) at q; NaN outside.
double At(const std::vector<double>& x, const std::vector<double>& y, double q) {
  if (x.size() < 2 || q < x.front() || q > x.back()) return NAN;
  const auto it = std::upper_bound(x.begin(), x.end(), q);
  const std::size_t j = std::min<std::size_t>(std::max<std::ptrdiff_t>(it - x.begin(), 1), x.size() - 1);
  const double w = (q - x[j - 1]) / (x[j] - x[j - 1]);
  return y[j - 1] + w * (y[j] - y[j - 1]);
}

// Largest relative difference of curve b from curve a at a's abscissae
// (both sorted by x first).
double LargestRelativeDifference(std::vector<double> xa, std::vector<double> ya,
                                 std::vector<double> xb, std::vector<double> yb) {
  auto sort = [](std::vector<double>& x, std::vector<double>& y) {
    std::vector<std::size_t> k(x.size());
    for (std::size_t i = 0; i < k.size(); ++i) k[i] = i;
    std::sort(k.begin(), k.end(), [&](auto i, auto j) { return x[i] < x[j]; });
    std::vector<double> xs, ys;
    for (auto i : k) xs.push_back(x[i]), ys.push_back(y[i]);
    x = xs, y = ys;
  };
  sort(xa, ya);
  sort(xb, yb);
  double worst = 0.0;
  for (std::size_t i = 0; i < xa.size(); ++i) {
    const double v = At(xb, yb, xa[i]);
    if (std::isfinite(v) && ya[i] != 0.0) worst = std::max(worst, std::abs(v / ya[i] - 1.0));
  }
  return worst;
}

// Every record row is either an R point or counted under a reason.
void ExpectEveryRowCounted(const FitInput& input, const ExperimentRecord& record, const std::string& what) {
  ASSERT_TRUE(input.reduction.has_value()) << what;
  int dropped = 0;
  for (const auto& item : input.dropped_rows) dropped += item.second;
  // Rows the import already set aside (exact repeats, NaN in a used column)
  // are in the list too.
  EXPECT_EQ(input.reduction->points_used + dropped,
            static_cast<int>(record.size()) + record.rows_dropped_nan + record.rows_repeated)
      << what;
}

// The in-process R curve (what `fit RECORD` reduces; the load fit's start)
// and the README chain (mbt, then the fit of that R curve): both run, every
// row counted, and the fitted R stays with the clean record's.
class FaultedRCurveFit : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(FaultedRCurveFit, RunsCountsEveryRowAndStaysWithTheCleanFit) {
  const auto [c, f] = GetParam();
  const NamedFault fault = RecordFaults().at(f);
  const FitRequest base = BaseRequest(kCases[c], ModelChoice::kAnalytic);
  const ExperimentRecord clean_record = ReadDcb(kCases[c].file);
  const ExperimentRecord record = fault.apply(clean_record);
  const std::string what = kCases[c].file + ", " + fault.name;

  // fit RECORD: the in-process energy R curve (>= 4 points, else the
  // specimen's point-wise method, said in a note).
  FitRequest in_process = base;
  in_process.record = record;
  const FitRun e = RunFit(in_process);
  ExpectEveryRowCounted(e.input, record, what + " (in-process)");
  EXPECT_GE(e.input.curve.size(), 10u) << what << ": " << e.input.curve.method;
  EXPECT_EQ(e.input.curve.method, "energy") << what;
  EXPECT_TRUE(e.summary.converged) << what << ": " << e.summary.stop_reason;

  // 100,000 rows: the in-process route above is the check (its MBT R curve
  // has ~90,000 points, and one fit of them takes about a minute: timed in
  // docs/RCURVE_METHODS.md, not here).
  if (record.size() > 20000) return;

  // README chain. The reference is the clean record with the same rows
  // measured: a crack-length column that ends early (NaN tail) gives R points
  // only as far as the readings go, so its like is the clean record cut there.
  ExperimentRecord reference = clean_record;
  if (fault.name.find("NaN tail") != std::string::npos) {
    const std::size_t keep = clean_record.size() - 55;
    for (std::vector<double>* v : {&reference.load, &reference.displacement, &reference.crack_length,
                                   &reference.time})
      if (v->size() > keep) v->resize(keep);
  }
  const FitRun clean = FitOfRCurve(base, reference);
  const FitRun m = FitOfRCurve(base, record);
  EXPECT_TRUE(m.summary.converged) << what << ": " << m.summary.stop_reason;
  const double diff = LargestRelativeDifference(clean.summary.fitted_crack_length, clean.summary.fitted_R,
                                                m.summary.fitted_crack_length, m.summary.fitted_R);
  std::printf("%-60s in-process energy %2zu points, %.2f s; mbt fit %.2f s, model R max diff %.3f%%, "
              "sigma_c %.4g (clean %.4g) MPa\n",
              what.c_str(), e.input.curve.size(), e.summary.wall_s, m.summary.wall_s, 100 * diff,
              m.summary.sigma_c.value * 1e-6, clean.summary.sigma_c.value * 1e-6);
  EXPECT_LT(diff, 0.01) << what;
}

INSTANTIATE_TEST_SUITE_P(IssueFaults, FaultedRCurveFit,
                         ::testing::Combine(::testing::Values(0, 1), ::testing::Range(0, 7)));

// The load fit with the compliance calibrated along the crack (docs/FIT.md's
// command) against the clean record's: it runs, calibrates, counts every
// row, and its model load moves by less than the clean fit's own rms misfit
// to the record. On the synthetic MDF CT sample (1 mm elements, about a
// second a fit) each fault of the issue's list (the
// 100,000-row resampling apart: bench/rcurve_rows_bench.sh); on the real DCBs
// (0.6 mm elements, about a minute a fit on the 2-core machine) every fault
// at once, with BRIDGEFIT_LONG_TESTS=1 (figures in docs/RCURVE_METHODS.md).
struct LoadFitCase {
  FitRequest base;
  ExperimentRecord clean, faulted;
  std::string what;
};

void CheckLoadFit(const LoadFitCase& c) {
  const FitRun clean = LoadFit(c.base, c.clean);
  const FitRun l = LoadFit(c.base, c.faulted);
  ExpectEveryRowCounted(l.input, c.faulted, c.what);
  EXPECT_TRUE(l.summary.converged) << c.what << ": " << l.summary.stop_reason;
  EXPECT_TRUE(l.calibration.calibrated()) << c.what;
  ASSERT_TRUE(clean.summary.converged) << clean.summary.stop_reason;
  // The model's load at the clean fit's rows, faulted fit against clean fit.
  const std::vector<double>& d = l.summary.fitted_displacement;
  std::vector<std::size_t> order(d.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto i, auto j) { return d[i] < d[j]; });
  std::vector<double> ds, Ps;
  for (auto i : order) ds.push_back(d[i]), Ps.push_back(l.summary.fitted_load[i]);
  double worst = 0.0, worst_relative = 0.0;
  for (std::size_t i = 0; i < clean.summary.fitted_displacement.size(); ++i) {
    const double v = At(ds, Ps, clean.summary.fitted_displacement[i]);
    if (!std::isfinite(v)) continue;
    worst = std::max(worst, std::abs(v - clean.summary.fitted_load[i]));
    worst_relative = std::max(worst_relative, std::abs(v / clean.summary.fitted_load[i] - 1.0));
  }
  std::printf("%s: load fit %.2f s (clean %.2f s), %zu rows (clean %zu), chi^2 %.4g (clean %.4g), "
              "model P max diff %.3g N (%.3f%%; clean rms misfit %.3g N), sigma_c %.4g (clean %.4g) "
              "MPa, J_tip_c %.4g (clean %.4g) J/m^2, modulus x %.4f (clean %.4f)\n",
              c.what.c_str(), l.summary.wall_s, clean.summary.wall_s, l.load_data->size(),
              clean.load_data->size(), l.summary.chi2, clean.summary.chi2, worst,
              100 * worst_relative, clean.summary.rms_residual, l.summary.sigma_c.value * 1e-6,
              clean.summary.sigma_c.value * 1e-6, l.summary.J_tip_c.value, clean.summary.J_tip_c.value,
              l.calibration.modulus_factor, clean.calibration.modulus_factor);
  EXPECT_LT(worst, clean.summary.rms_residual) << c.what;
}

LoadFitCase MdfCase(const NamedFault& fault) {
  LoadFitCase c;
  c.base = BaseRequest({"", "../mdf_ct/scene.toml"}, ModelChoice::kReduced);
  c.base.resolution = 1e-3;
  c.base.fit.starts = inverse::FitOptions{}.starts;  // the command line's default
  c.clean = io::ReadRecordCsv(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/record.csv",
                              io::RecordColumns{});
  c.faulted = fault.apply(c.clean);
  c.what = "mdf_ct, " + fault.name;
  return c;
}

class FaultedCtLoadFit : public ::testing::TestWithParam<int> {};

// Every fault of the issue's list but the 100,000-row resampling. The NaN
// tail (3) was a known failure until the models grew past the record's last
// row rather than its last crack reading (src/pipeline/fit_models.cpp):
// sigma_c 0.70 MPa at chi^2 2.6e5 (1 start) or 0.42 MPa at 3.4e4 (4 starts),
// against 0.447 MPa at 664 for the clean record, reported converged.
TEST_P(FaultedCtLoadFit, RunsAndStaysWithTheCleanFit) { CheckLoadFit(MdfCase(RecordFaults().at(GetParam()))); }

INSTANTIATE_TEST_SUITE_P(IssueFaults, FaultedCtLoadFit, ::testing::Values(0, 1, 2, 3, 4, 5));

// The same mechanism on a fault the issue did not list, and on the other CT
// sample (no bridging): a camera that stopped when the crack had grown half
// its final length, every later reading NaN (about half the growth rows).
LoadFitCase CameraStoppedCase(const std::string& sample) {
  LoadFitCase c;
  c.base = BaseRequest({"", "../" + sample + "/scene.toml"}, ModelChoice::kReduced);
  c.base.resolution = 1e-3;
  c.base.fit.starts = inverse::FitOptions{}.starts;
  c.clean = io::ReadRecordCsv(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/" + sample + "/record.csv",
                              io::RecordColumns{});
  c.faulted = c.clean;
  const double a0 = c.clean.crack_length.front();
  const double half = a0 + 0.5 * (*std::max_element(c.clean.crack_length.begin(), c.clean.crack_length.end()) - a0);
  std::size_t stopped = 0;
  for (std::size_t i = 0; i < c.faulted.size(); ++i) {
    if (c.clean.crack_length[i] > half) c.faulted.crack_length[i] = NAN, ++stopped;
  }
  EXPECT_GT(stopped, c.clean.size() / 5) << sample;
  c.what = sample + ", crack readings stopped at half the growth (" + std::to_string(stopped) + " rows NaN)";
  return c;
}

TEST(CameraStoppedLoadFit, MdfCtStaysWithTheCleanFit) { CheckLoadFit(CameraStoppedCase("mdf_ct")); }
TEST(CameraStoppedLoadFit, ParticleBoardCtStaysWithTheCleanFit) { CheckLoadFit(CameraStoppedCase("pb_ct")); }

class FaultedDcbLoadFit : public ::testing::TestWithParam<int> {};

TEST_P(FaultedDcbLoadFit, AllIssueFaultsAtOnceRunAndStayWithTheCleanFit) {
  const DcbCase& dcb = kCases[GetParam()];
  if (!std::getenv("BRIDGEFIT_LONG_TESTS"))
    GTEST_SKIP() << dcb.file << ": about a minute per load fit; set BRIDGEFIT_LONG_TESTS=1 to run it";
  LoadFitCase c;
  c.base = BaseRequest(dcb, ModelChoice::kReduced);
  c.clean = ReadDcb(dcb.file);
  c.faulted = testing::AllIssueFaults(c.clean);
  c.what = dcb.file + ", every fault of the issue's list";
  CheckLoadFit(c);
}

INSTANTIATE_TEST_SUITE_P(DcbRecords, FaultedDcbLoadFit, ::testing::Values(0, 1));

}  // namespace
}  // namespace bridgefit::pipeline
