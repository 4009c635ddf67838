// `fit --law bilinear|trilinear|table` alone (issue 21) through
// pipeline::RunFit, the fit file and the report. Oracles: R curves of the
// analytic model the fit uses (tests/inverse/shape_data.hpp); the fit file
// read back bit for bit; the report's law table and curve against the
// fitted shape's sigma(delta).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../inverse/shape_data.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/pipeline/report_file.hpp"

namespace bridgefit::pipeline {
namespace {

namespace fs = std::filesystem;

struct WorkDir {
  fs::path path = fs::temp_directory_path() / ("bf_shape_law_" + std::to_string(::getpid()));
  WorkDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~WorkDir() { fs::remove_all(path); }
};

// A CT large enough for the data (the analytic model reads E' and a0 only):
// E' = 1 GPa (plane stress), a0 = 30 mm, as tests/inverse/fit_shape_test.cpp.
Scene AnalyticScene() {
  Scene scene;
  scene.source = "shape law test CT";
  scene.specimen.type = SpecimenType::kCT;
  scene.specimen.width = 0.200;
  scene.specimen.height = 0.240;
  scene.specimen.thickness = 0.010;
  scene.specimen.notch = 0.030;
  scene.specimen.plane = PlaneCondition::kPlaneStress;
  scene.material.E = 1e9;
  scene.material.nu = 0.3;
  return scene;
}

// The analytic model's R for `shape` as an in-memory R curve request.
FitRequest ShapeRequest(const std::string& law, const laws::LawShape& shape,
                        const inverse::LawParameters& truth, int points, unsigned seed) {
  FitRequest request;
  request.scene = AnalyticScene();
  request.scene_path = request.scene.source;
  request.model = ModelChoice::kAnalytic;
  request.fit.profile_likelihood = false;
  request.fit.starts = 3;
  SetFitLaw(law, request);
  const auto model = inverse::MakeAnalyticForwardModel(request.scene);
  const double a0 = request.scene.specimen.notch;
  const inverse::FitData data =
      inverse::testing::MakeShapeData(*model, a0, shape, truth, a0 + 0.08, points, 0.005, seed);
  RCurve curve;
  curve.method = "energy";
  curve.r_kind = "energy";
  curve.source = "analytic model, " + law;
  curve.crack_length = data.crack_length;
  curve.R = data.R;
  curve.R_uncertainty = data.R_uncertainty;
  curve.initial_crack_length = a0;
  request.rcurve = curve;
  return request;
}

// Numbers of a gnuplot table (comment lines skipped).
std::vector<std::vector<double>> ReadTable(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    for (std::string v; fields >> v;) row.push_back(std::stod(v));
    rows.push_back(row);
  }
  return rows;
}

// Issue 21's acceptance with the table fitted alone: the cubic law's R
// (400 points, 0.5% noise, as FitShape.TableFollowsTheCubicLaw): every knot
// within 5% of sigma_c of the cubic at its opening; the fit file holds the
// shape bit for bit (interpolation too); the report's law table and the
// curve it draws equal the fitted sigma(delta) at every knot.
TEST(PipelineShapeLaw, TableAloneFollowsTheCubicLawIntoTheFileAndTheReport) {
  const WorkDir work;
  const laws::LawShape cubic = laws::MakeCubicShape();
  const inverse::LawParameters truth{1.0e6, 500.0, 2210.0};
  const FitRequest request = ShapeRequest("table", cubic, truth, 400, 31);
  const FitRun run = RunFit(request);
  std::printf("%s", run.BriefReport().c_str());
  ASSERT_TRUE(run.summary.converged) << run.summary.verdict;
  EXPECT_EQ(run.summary.law, "table");
  EXPECT_EQ(run.fitted_shape.family, "table");
  ASSERT_EQ(run.shape.family, laws::LawFamily::kTable);
  EXPECT_EQ(run.shape.interpolation, laws::TableInterpolation::kMonotoneCubic);
  EXPECT_EQ(run.fitted_shape.knots + 1, static_cast<int>(run.shape.d_points.size()));
  EXPECT_EQ(run.fitted_shape.parameters.size(), static_cast<size_t>(run.fitted_shape.knots));
  const double sigma_c = run.summary.sigma_c.value, delta_c = run.summary.delta_c.value;
  const double true_delta_c = truth.J_B / (cubic.Area() * truth.sigma_c);
  double worst = 0.0;
  for (size_t k = 0; k < run.shape.d_points.size(); ++k) {
    const double delta = run.shape.d_points[k] * delta_c;
    const double fitted = sigma_c * run.shape.s_points[k];
    const double expected = truth.sigma_c * laws::ShapeValue(cubic, delta / true_delta_c);
    std::printf("  knot d = %.3f: sigma %.4f MPa, cubic %.4f MPa\n", run.shape.d_points[k],
                fitted * 1e-6, expected * 1e-6);
    worst = std::max(worst, std::abs(fitted - expected) / truth.sigma_c);
  }
  std::printf("  worst knot error %.4f sigma_c\n", worst);
  EXPECT_LE(worst, 0.05);

  const fs::path fit_h5 = work.path / "fit.h5";
  WriteFitFile(fit_h5.string(), request, run);
  const FittedLaw read = ReadFittedLaw(fit_h5);
  EXPECT_EQ(read.shape.family, run.shape.family);
  EXPECT_EQ(read.shape.interpolation, run.shape.interpolation);
  EXPECT_EQ(read.shape.d_points, run.shape.d_points);
  EXPECT_EQ(read.shape.s_points, run.shape.s_points);

  const fs::path out = work.path / "report";
  WriteFitReport(fit_h5, out);
  const laws::BridgingLaw law{&run.shape, sigma_c, delta_c};
  const auto points = ReadTable(out / "law_points.dat");  // d s delta[mm] sigma[MPa]
  ASSERT_EQ(points.size(), run.shape.d_points.size());
  const auto curve = ReadTable(out / "law.dat");  // delta[mm] lower upper best truth
  for (size_t k = 0; k < points.size(); ++k) {
    const double delta = run.shape.d_points[k] * delta_c;
    EXPECT_NEAR(points[k][2], delta * 1e3, 1e-7 * delta_c * 1e3) << k;
    EXPECT_NEAR(points[k][3], law.Traction(delta) * 1e-6, 1e-7) << k;
    // The drawn curve passes through the knot (it is one of its openings).
    bool found = false;
    for (const auto& row : curve)
      if (std::abs(row[0] - delta * 1e3) <= 1e-7 * delta_c * 1e3) {
        found = true;
        EXPECT_NEAR(row[3], law.Traction(delta) * 1e-6, 1e-7) << k;
      }
    EXPECT_TRUE(found) << "knot " << k << " not on the drawn curve";
  }
  std::ifstream page(out / "index.html");
  const std::string html((std::istreambuf_iterator<char>(page)), {});
  EXPECT_NE(html.find("id=\"law_shape\""), std::string::npos);
  EXPECT_NE(html.find("monotone cubic (PCHIP)"), std::string::npos);
  EXPECT_NE(html.find("95% Wald interval"), std::string::npos);
  EXPECT_EQ(html.find("drawn with the linear shape"), std::string::npos);
}

// A bilinear law (kink at d = 0.25, s = 0.3, as FitShape.BilinearRecoversItsKink)
// fitted alone: the kink within its 95% Wald intervals, the scale
// parameters within theirs; the summary says the intervals are Wald.
TEST(PipelineShapeLaw, BilinearAloneRecoversItsKink) {
  laws::LawShape bilinear{.family = laws::LawFamily::kTable};
  bilinear.d_points = {0.0, 0.25, 1.0};
  bilinear.s_points = {1.0, 0.3, 0.0};
  const inverse::LawParameters truth{2.0e6, 500.0, 2210.0};
  const FitRun run = RunFit(ShapeRequest("bilinear", bilinear, truth, 100, 41));
  const std::string text = run.BriefReport();
  std::printf("%s", text.c_str());
  ASSERT_TRUE(run.summary.converged) << run.summary.verdict;
  EXPECT_EQ(run.summary.law, "bilinear");
  EXPECT_NE(text.find("95% Wald ["), std::string::npos);
  ASSERT_EQ(run.fitted_shape.parameters.size(), 2u);
  const double expected[] = {0.25, 0.3};
  for (int k = 0; k < 2; ++k) {
    const inverse::ShapeParameter& p = run.fitted_shape.parameters[k];
    ASSERT_TRUE(std::isfinite(p.standard_error)) << p.name;
    EXPECT_LE(std::abs(p.value - expected[k]), 1.96 * p.standard_error) << p.name;
  }
  const double truths[] = {truth.sigma_c, truth.J_B, truth.J_tip_c};
  const inverse::ParameterEstimate* estimates[] = {&run.summary.sigma_c, &run.summary.J_B,
                                                   &run.summary.J_tip_c};
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(estimates[i]->ci95_low, truths[i]) << i;
    EXPECT_GE(estimates[i]->ci95_high, truths[i]) << i;
  }
}

// `--law compare` on the same bilinear data (the fixed families and the
// bilinear one): the bilinear law wins by AICc, and the run's law is its
// row's shape with its parameters, written to the fit file and read back
// as the report's view (not a linear stand-in).
TEST(PipelineShapeLaw, CompareWinnerCarriesItsFittedShape) {
  const WorkDir work;
  laws::LawShape bilinear{.family = laws::LawFamily::kTable};
  bilinear.d_points = {0.0, 0.25, 1.0};
  bilinear.s_points = {1.0, 0.3, 0.0};
  FitRequest request = ShapeRequest("compare", bilinear, {2.0e6, 500.0, 2210.0}, 100, 41);
  request.shape_families = {inverse::ShapeFamily::kBilinear};
  const FitRun run = RunFit(request);
  ASSERT_EQ(run.comparison.size(), 5u);
  const inverse::LawComparison& row = run.comparison.back();
  ASSERT_EQ(row.law, "bilinear");
  EXPECT_EQ(row.delta_aicc, 0.0) << "bilinear not chosen";
  EXPECT_EQ(run.summary.law, "bilinear");
  EXPECT_EQ(run.fitted_shape.family, "bilinear");
  EXPECT_EQ(run.shape.d_points, row.shape.d_points);
  EXPECT_EQ(run.shape.s_points, row.shape.s_points);
  ASSERT_EQ(run.fitted_shape.parameters.size(), 2u);
  EXPECT_EQ(run.fitted_shape.parameters[0].value, row.shape_parameters[0].value);

  const fs::path fit_h5 = work.path / "compare.h5";
  WriteFitFile(fit_h5.string(), request, run);
  const report::FitView view = ReadFitView(fit_h5);
  EXPECT_EQ(view.law, "bilinear");
  EXPECT_EQ(view.fitted_shape, "bilinear");
  ASSERT_TRUE(view.shape);
  EXPECT_EQ(view.shape->d_points, run.shape.d_points);
  EXPECT_EQ(view.shape->s_points, run.shape.s_points);
  ASSERT_EQ(view.shape_parameters.size(), 2u);
  EXPECT_EQ(view.shape_parameters[0].name, "d1");
}

// Each shape the fit can hold (the four fixed families, bilinear,
// trilinear, the PCHIP table) with a fitted shape's parameters: written by
// WriteFitFile, read by ReadFittedLaw and ReadFitView, bit for bit.
TEST(PipelineShapeLaw, EveryShapeRoundTripsThroughTheFitFileExactly) {
  const WorkDir work;
  const FitRequest request = ShapeRequest("linear", laws::MakeLinearShape(),
                                          {1.0e6, 500.0, 2210.0}, 20, 3);
  FitRun run = RunFit(request);
  laws::LawShape bilinear{.family = laws::LawFamily::kTable};
  bilinear.d_points = {0.0, 0.2371, 1.0};
  bilinear.s_points = {1.0, 0.31234567891, 0.0};
  laws::LawShape table{.family = laws::LawFamily::kTable};
  table.d_points = {0.0, 0.2, 0.4, 0.6, 0.8, 1.0};
  table.s_points = {0.3141592653589793, 1.0, 0.77, 0.4, 0.1234, 0.0};
  table.interpolation = laws::TableInterpolation::kMonotoneCubic;
  const laws::LawShape shapes[] = {laws::MakeLinearShape(), laws::MakeCubicShape(),
                                   laws::MakeTriangularShape(0.173),
                                   laws::MakeExponentialShape(2.71828),
                                   bilinear,
                                   laws::MakeTrilinearShape(0.5, 0.1, 1.0, 0.4, 0.3),
                                   table};
  const char* fitted[] = {"", "", "", "", "bilinear", "trilinear", "table"};
  for (size_t i = 0; i < std::size(shapes); ++i) {
    run.shape = shapes[i];
    run.fitted_shape = {};
    run.fitted_shape.family = fitted[i];
    if (run.fitted_shape.fitted()) {
      run.fitted_shape.knots = i == 6 ? 5 : 0;
      run.fitted_shape.note = "N = 5 knots chosen by AICc";
      run.fitted_shape.parameters = {{"d1", 0.2371, 0.0123456789, false},
                                     {"s1", 1.0, NAN, true},
                                     {"s(0.2)", 0.77, 1.5e-3, false}};
    }
    const fs::path file = work.path / ("shape" + std::to_string(i) + ".h5");
    WriteFitFile(file.string(), request, run);
    const laws::LawShape& a = shapes[i];
    const FittedLaw law = ReadFittedLaw(file);
    const report::FitView view = ReadFitView(file);
    ASSERT_TRUE(view.shape) << i << ": " << view.shape_note;
    for (const laws::LawShape* b : {&law.shape, &*view.shape}) {
      EXPECT_EQ(b->family, a.family) << i;
      EXPECT_EQ(b->interpolation, a.interpolation) << i;
      EXPECT_EQ(b->peak_ratio, a.peak_ratio) << i;
      EXPECT_EQ(b->alpha, a.alpha) << i;
      EXPECT_EQ(b->d_points, a.d_points) << i;
      EXPECT_EQ(b->s_points, a.s_points) << i;
    }
    EXPECT_TRUE(view.shape_note.empty()) << view.shape_note;
    EXPECT_EQ(view.fitted_shape, run.fitted_shape.family) << i;
    EXPECT_EQ(view.shape_knots, run.fitted_shape.knots) << i;
    ASSERT_EQ(view.shape_parameters.size(), run.fitted_shape.parameters.size()) << i;
    for (size_t k = 0; k < view.shape_parameters.size(); ++k) {
      const inverse::ShapeParameter& p = run.fitted_shape.parameters[k];
      const report::FitView::ShapeParameter& q = view.shape_parameters[k];
      EXPECT_EQ(q.name, p.name);
      EXPECT_EQ(q.value, p.value);
      EXPECT_EQ(std::isnan(q.standard_error), std::isnan(p.standard_error));
      if (!std::isnan(p.standard_error)) {
        EXPECT_EQ(q.standard_error, p.standard_error);
      }
      EXPECT_EQ(q.pinned, p.pinned);
    }
    // The break points at the fitted scales, in SI with their units.
    if (!a.d_points.empty()) {
      const io::H5Reader r(file);
      std::string units;
      const std::vector<double> sigma = r.ReadVector("/fit/law_shape/sigma_points", &units);
      EXPECT_EQ(units, "Pa");
      ASSERT_EQ(sigma.size(), a.s_points.size());
      EXPECT_EQ(sigma[1], a.s_points[1] * run.summary.sigma_c.value);
      EXPECT_EQ(r.ReadVector("/fit/law_shape/delta_points", &units)[1],
                a.d_points[1] * run.summary.delta_c.value);
      EXPECT_EQ(units, "m");
    }
  }
}

// A fit file written before the interpolation was stored: its table reads
// with straight segments, said; one without /fit/law_shape for a table law
// reads with no shape, said (the report draws the linear law and says so).
TEST(PipelineShapeLaw, OlderFitFilesReadWithTheFallbackSaid) {
  const WorkDir work;
  const fs::path file = work.path / "old.h5";
  {
    io::H5Writer w(file);
    w.WriteVector("/fit/crack_length", {0.03, 0.04}, "m");
    w.WriteVector("/fit/R", {2300.0, 2500.0}, "J/m^2");
    w.WriteAttribute("/fit", "law", "table");
    w.WriteAttribute("/fit/law_shape", "family", "table");
    w.WriteVector("/fit/law_shape/d_points", {0.0, 0.5, 1.0}, "1");
    w.WriteVector("/fit/law_shape/s_points", {1.0, 0.4, 0.0}, "1");
    w.Commit();
  }
  const report::FitView view = ReadFitView(file);
  ASSERT_TRUE(view.shape);
  EXPECT_EQ(view.shape->interpolation, laws::TableInterpolation::kLinear);
  EXPECT_NE(view.shape_note.find("interpolation is not in the file"), std::string::npos)
      << view.shape_note;
  EXPECT_TRUE(view.fitted_shape.empty());

  const fs::path older = work.path / "older.h5";
  {
    io::H5Writer w(older);
    w.WriteVector("/fit/crack_length", {0.03, 0.04}, "m");
    w.WriteVector("/fit/R", {2300.0, 2500.0}, "J/m^2");
    w.WriteAttribute("/fit", "law", "table");
    w.Commit();
  }
  const report::FitView none = ReadFitView(older);
  EXPECT_FALSE(none.shape);
  EXPECT_NE(none.shape_note.find("does not hold the shape"), std::string::npos) << none.shape_note;
}

Error Thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no Error thrown";
  return Error(ErrorKind::kRuntime, "none");
}

// Bad choices name the flag and what it takes: an unknown law, one knot,
// a shape family alone together with compare, and data too few for any
// knot count (an input error, after reading, with the way out).
TEST(PipelineShapeLaw, BadRequestsNameTheFlag) {
  FitRequest request = ShapeRequest("table", laws::MakeCubicShape(), {1.0e6, 500.0, 2210.0}, 6, 5);
  std::string why;
  EXPECT_TRUE(request.IsValid(&why)) << why;
  Error e = Thrown([&] { SetFitLaw("quadratic", request); });
  EXPECT_EQ(e.kind(), ErrorKind::kUsage);
  EXPECT_EQ(e.context().field, "--law");
  EXPECT_NE(e.context().expected.find("bilinear, trilinear or table"), std::string::npos);

  FitRequest bad = request;
  bad.shape_fit.table_knots = {1};
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("--table-knots"), std::string::npos) << why;
  EXPECT_NE(why.find("1 not in 2 .. 20"), std::string::npos) << why;

  bad = request;
  bad.compare_laws = true;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("--law"), std::string::npos) << why;

  // 6 points: N = 3 needs 3 + 2 free parameters and 7 points.
  e = Thrown([&] { RunFit(request); });
  EXPECT_EQ(e.kind(), ErrorKind::kInput);
  EXPECT_EQ(e.context().field, "--law");
  EXPECT_EQ(e.context().value, "table");
  EXPECT_NE(std::string(e.what()).find("too few"), std::string::npos) << e.what();
  EXPECT_NE(e.context().expected.find("--table-knots"), std::string::npos);

  SetFitLaw("bilinear", request);
  EXPECT_NE(std::string(Thrown([&] { RunFit(request); }).what())
                .find("6 data points are too few for its 5 parameters"),
            std::string::npos);
  // And back to a fixed shape: the same request fits.
  SetFitLaw("cubic", request);
  EXPECT_FALSE(request.shape_law);
  EXPECT_TRUE(RunFit(request).summary.converged);
}

}  // namespace
}  // namespace bridgefit::pipeline
