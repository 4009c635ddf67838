// `bridgefit lawfree` as a call (issue 21): the /dic J columns -> RunLawFree
// -> /lawfree, against the exact law of the data (linear softening, PHYSICS
// eqs. 1 and 3), the /lawfree round trip, and bad input.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"

namespace bridgefit::pipeline {
namespace {
namespace fs = std::filesystem;

// Linear softening: sigma_c = 1 MPa, delta_c = 0.4 mm, J_tip,c = 300 J/m^2.
constexpr double kSigmaC = 1e6, kDeltaC = 0.4e-3, kJtip = 300, kA0 = 30e-3;
double Sigma(double d) { return d < kDeltaC ? kSigmaC * (1 - d / kDeltaC) : 0.0; }
double Work(double d) {
  const double x = std::min(d, kDeltaC);
  return kSigmaC * (x - x * x / (2 * kDeltaC));
}

fs::path TempDir(const char* name) {
  const fs::path d = fs::temp_directory_path() / fmt::format("bf_lawfree_{}_{}", name, getpid());
  fs::create_directories(d);
  return d;
}

// A DIC run whose frames carry J_ff = J_tip,c + W(delta*) exactly (eq. 1),
// delta* rising to 0.8 delta_c, crack length linear in delta*; frame 0 is
// the reference, frame `failed` has no far-field domain.
dic::CrackSequenceResult ExactRun(int frames, int failed) {
  dic::CrackSequenceResult r;
  r.j_integral = true;
  for (int k = 0; k < frames; ++k) {
    dic::FrameResult f;
    f.image = fmt::format("frame_{:02d}.png", k);
    if (k == 0) {
      f.j.status = dic::FrameJStatus::kNoTip;
      f.j.why = "reference frame";
      r.frames.push_back(f);
      continue;
    }
    const double delta = 0.8 * kDeltaC * (k - 1) / (frames - 2);
    f.has_length = true;
    f.crack_length_m = f.crack_length_raw_m = kA0 + 50 * delta;
    f.tip.tip.found = true;
    f.j.domains = 3;
    if (k == failed) {
      f.j.status = dic::FrameJStatus::kNoFarFieldDomain;
      f.j.why = "r 10-20 pt: leaves field";
    } else {
      f.j.status = dic::FrameJStatus::kOk;
      f.j.domains_ok = 3;
      f.j.J_ff = kJtip + Work(delta);
      f.j.J_ff_spread_percent = 0.5;
    }
    f.j.delta_star_ok = true;
    f.j.delta_star = delta;
    f.j.delta_star_uncertainty = 1e-7;
    r.frames.push_back(f);
  }
  return r;
}

dic::CrackSequenceOptions JOptions() {
  dic::CrackSequenceOptions o;
  o.scale_m_per_px = 1e-4;
  o.j_integral.enabled = true;
  o.j_integral.elastic = dic::ElasticConstants::Isotropic(3e9, 0.3);
  o.j_integral.notch_length_m = kA0;
  return o;
}

TEST(LawFree, JRouteRecoversTheLawAndSkipsAFailedFrameWithANote) {
  const fs::path dir = TempDir("jroute");
  const dic::CrackSequenceResult run = ExactRun(26, 7);
  WriteDicH5((dir / "dic.h5").string(), run, JOptions());
  WriteDicCsv((dir / "dic.csv").string(), run);
  // The CSV names its units and says why frame 7 has no J.
  const io::CsvTable csv = io::ReadCsvTable(dir / "dic.csv");
  ASSERT_GE(csv.Find("J_ff"), 0);
  EXPECT_EQ(csv.TextColumn("J_status")[7], "no_far_field_domain");
  EXPECT_TRUE(std::isnan(csv.columns[csv.Find("J_ff")][7]));
  EXPECT_NEAR(csv.ColumnSi("delta_star", Dimension::Length())[5], run.frames[5].j.delta_star, 1e-9);

  LawFreeRequest request;
  request.dic_file = dir / "dic.h5";
  request.onset_opening = 0.0;
  const LawFreeRun out = RunLawFree(request);
  std::printf("%s", out.BriefReport().c_str());
  ASSERT_TRUE(out.far_field.has_value());
  EXPECT_EQ(out.far_field->points_used, 24);  // 25 frames with a tip, one failed
  bool noted = false;
  for (const std::string& n : out.notes) noted = noted || n.find("frame 7 ") != std::string::npos;
  EXPECT_TRUE(noted) << "no note on the skipped frame";
  EXPECT_NEAR(out.far_field->J_tip_c, kJtip, 0.01 * kJtip);
  // sigma within 5 % of sigma_c over the covered openings (exact data: the
  // only error is the penalised spline's).
  double worst = 0;
  for (size_t j = 0; j < out.far_field->delta.size(); ++j) {
    const double d = out.far_field->delta[j];
    if (d > 0.8 * kDeltaC) continue;
    worst = std::max(worst, std::abs(out.far_field->sigma[j] - Sigma(d)) / kSigmaC);
  }
  std::printf("J route on exact data: worst |sigma error| %.2f %% of sigma_c\n", 100 * worst);
  EXPECT_LT(worst, 0.05);
  EXPECT_FALSE(out.far_field->J_B.identified);  // 0.8 delta_c: no plateau, a lower bound
  fs::remove_all(dir);
}

TEST(LawFree, RRouteMatchesRPointsToFramesByCrackLength) {
  const fs::path dir = TempDir("rroute");
  // delta* to 1.6 delta_c (steady state reached): the R route is identified.
  dic::CrackSequenceResult run = ExactRun(30, -1);
  for (size_t k = 1; k < run.frames.size(); ++k) {
    const double delta = 1.6 * kDeltaC * (k - 1) / (run.frames.size() - 2);
    run.frames[k].j.delta_star = delta;
    run.frames[k].crack_length_m = kA0 + 50 * delta;
  }
  WriteDicH5((dir / "dic.h5").string(), run, JOptions());
  // R points between the frames (eq. 3), some outside them.
  std::string csv = "crack_length [mm], R [J/m^2], R_uncertainty [J/m^2]\n";
  for (int i = 0; i < 60; ++i) {
    const double delta = 1.7 * kDeltaC * (i + 0.5) / 60;
    const double R = kJtip + Work(delta) - 0.5 * Sigma(delta) * delta;
    csv += fmt::format("{:.9g}, {:.9g}, 1\n", (kA0 + 50 * delta) * 1e3, R);
  }
  WriteTextFileAtomic(dir / "rcurve.csv", csv);
  LawFreeRequest request;
  request.dic_file = dir / "dic.h5";
  request.rcurve_file = dir / "rcurve.csv";
  request.far_field_route = false;
  const LawFreeRun out = RunLawFree(request);
  std::printf("%s", out.BriefReport().c_str());
  ASSERT_TRUE(out.r_curve.has_value());
  EXPECT_FALSE(out.far_field.has_value());
  EXPECT_LT(out.r_curve->points_used, 60);  // those beyond 1.6 delta_c skipped ...
  bool noted = false;
  for (const std::string& n : out.notes) noted = noted || n.find("outside the frames") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_NEAR(out.r_curve->J_tip_c, kJtip, 0.02 * kJtip);
  double worst = 0;
  for (size_t j = 0; j < out.r_curve->delta.size(); ++j)
    worst = std::max(worst, std::abs(out.r_curve->sigma[j] - Sigma(out.r_curve->delta[j])) / kSigmaC);
  std::printf("R route on exact data: worst |sigma error| %.2f %% of sigma_c, identified %d\n",
              100 * worst, out.r_curve->identified);
  EXPECT_LT(worst, 0.08);
  fs::remove_all(dir);
}

TEST(LawFree, WriterAndReaderRoundTrip) {
  const fs::path dir = TempDir("roundtrip");
  const dic::CrackSequenceResult run = ExactRun(20, 4);
  WriteDicH5((dir / "dic.h5").string(), run, JOptions());
  LawFreeRequest request;
  request.dic_file = dir / "dic.h5";
  const LawFreeRun out = RunLawFree(request);
  WriteLawFreeH5(dir / "lawfree.h5", out);
  const LawFreeRun back = ReadLawFreeH5(dir / "lawfree.h5");
  EXPECT_EQ(back.dic_file, out.dic_file);
  EXPECT_EQ(back.frames, out.frames);
  EXPECT_EQ(back.notes, out.notes);
  ASSERT_TRUE(back.far_field.has_value());
  EXPECT_FALSE(back.r_curve.has_value());
  const laws::LawFreeResult &a = *out.far_field, &b = *back.far_field;
  EXPECT_EQ(b.delta, a.delta);
  EXPECT_EQ(b.sigma, a.sigma);
  EXPECT_EQ(b.sigma_standard_error, a.sigma_standard_error);
  EXPECT_EQ(b.sigma_lower, a.sigma_lower);
  EXPECT_EQ(b.sigma_upper, a.sigma_upper);
  EXPECT_EQ(b.J_tip_c, a.J_tip_c);
  EXPECT_EQ(b.J_B.value, a.J_B.value);
  EXPECT_EQ(b.J_B.identified, a.J_B.identified);
  EXPECT_EQ(b.delta_c.value, a.delta_c.value);
  EXPECT_EQ(b.delta_c.identified, a.delta_c.identified);
  EXPECT_EQ(b.identified, a.identified);
  EXPECT_EQ(b.points_used, a.points_used);
  EXPECT_EQ(b.onset_index, a.onset_index);
  EXPECT_EQ(b.notes, a.notes);
  EXPECT_EQ(back.j_samples.opening, out.j_samples.opening);
  EXPECT_EQ(back.j_samples.J_ff, out.j_samples.J_ff);
  // A file without /lawfree names itself and the group.
  try {
    ReadLawFreeH5(dir / "dic.h5");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/lawfree"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dic.h5"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(LawFree, DicFileWithoutJNamesTheFileTheFieldAndTheWayOut) {
  const fs::path dir = TempDir("noj");
  dic::CrackSequenceResult run = ExactRun(12, -1);
  run.j_integral = false;
  dic::CrackSequenceOptions o = JOptions();
  o.j_integral.enabled = false;
  WriteDicH5((dir / "dic.h5").string(), run, o);
  LawFreeRequest request;
  request.dic_file = dir / "dic.h5";
  try {
    RunLawFree(request);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    EXPECT_NE(what.find((dir / "dic.h5").string()), std::string::npos) << what;
    EXPECT_NE(what.find("/dic/J_ff"), std::string::npos) << what;
    EXPECT_NE(what.find("--j-integral"), std::string::npos) << what;
  }
  // An empty request is a usage error, not a crash.
  std::string why;
  EXPECT_FALSE(LawFreeRequest{}.IsValid(&why));
  EXPECT_THROW(RunLawFree(LawFreeRequest{}), Error);
  fs::remove_all(dir);
}

TEST(LawFree, FrameJOptionsFromTheScene) {
  Scene scene;
  scene.source = "scene.toml";
  scene.specimen.notch = 30e-3;
  scene.material.E = 3e9;
  scene.material.nu = 0.3;
  scene.specimen.plane = PlaneCondition::kPlaneStress;
  dic::FrameJOptions o = FrameJOptionsFromScene(scene);
  EXPECT_TRUE(o.enabled);
  EXPECT_EQ(o.notch_length_m, 30e-3);
  EXPECT_EQ(o.elastic.E, 3e9);
  EXPECT_EQ(o.elastic.nu, 0.3);
  // Plane strain, isotropic: the plane-stress pair with the same in-plane
  // response, E / (1 - nu^2) and nu / (1 - nu).
  scene.specimen.plane = PlaneCondition::kPlaneStrain;
  o = FrameJOptionsFromScene(scene);
  EXPECT_DOUBLE_EQ(o.elastic.E, 3e9 / (1 - 0.09));
  EXPECT_DOUBLE_EQ(o.elastic.nu, 0.3 / 0.7);
  scene.material.orthotropic = true;
  scene.material.E1 = 20e9;
  scene.material.E2 = 6e9;
  scene.material.G12 = 3e9;
  scene.material.nu12 = 0.3;
  try {
    FrameJOptionsFromScene(scene);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.toml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bridgefit::pipeline
