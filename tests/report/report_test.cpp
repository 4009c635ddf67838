// Report: page, figures and table from a fit file with known content, written
// by the fit file's writer; the page checked in headless Chromium (skipped,
// with a message, when absent).
#include "bridgefit/pipeline/report_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <fstream>
#include <map>
#include <iostream>
#include <regex>
#include <sstream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"
#include "figure_check.hpp"

namespace fs = std::filesystem;
using namespace bridgefit;
using report_check::CheckStatus;
using report_check::DumpDom;
using report_check::FindChromium;
using report_check::ImageSources;
using report_check::PngSize;

namespace {

std::string ReadText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("bf_report_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A profile sampled the way the fitter samples it (src/inverse/fit.cpp: step
// out from the optimum, doubling the step, until Delta chi^2 passes the
// threshold, then 5 bisections), on chi^2 = chi2_min + s2 ((v - v0) / sd)^2,
// whose 95% interval is v0 -+ 1.96 sd. Returns the sampled interval ends (the
// last points inside); `flat_above` keeps the upper side under the threshold
// up to `box_high` (open-ended profile, end NaN).
struct SampledProfile {
  std::vector<double> value, chi2;
  double low = NAN, high = NAN;
};
SampledProfile SampleProfile(double v0, double sd, double chi2_min, double s2, bool flat_above = false,
                             double box_high = NAN) {
  SampledProfile p;
  const double threshold = 3.84 * s2;
  auto chi2 = [&](double v) {
    const double z = (v - v0) / sd;
    return chi2_min + s2 * (flat_above && v > v0 ? 0.01 * z : z * z);
  };
  auto sample = [&](double v) {
    p.value.push_back(v);
    p.chi2.push_back(chi2(v));
    return p.chi2.back() - chi2_min <= threshold;
  };
  for (int direction : {-1, +1}) {
    double in = v0, step = 0.3 * sd;
    while (true) {
      double out = in + direction * step;
      if (direction > 0 && out >= box_high) out = box_high;
      if (out == in) break;  // box edge reached inside: open
      if (!sample(out)) {
        double lo = in, hi = out;
        for (int b = 0; b < 5; ++b) {
          const double mid = 0.5 * (lo + hi);
          (sample(mid) ? lo : hi) = mid;
        }
        (direction < 0 ? p.low : p.high) = lo;
        break;
      }
      in = out;
      step *= 2.0;
    }
  }
  p.value.push_back(v0);
  p.chi2.push_back(chi2_min);
  return p;
}

inverse::ParameterEstimate Estimate(double value, double lo, double hi, double lower_bound,
                                    bool identified) {
  inverse::ParameterEstimate e;
  e.value = value;
  e.ci95_low = lo;
  e.ci95_high = hi;
  e.lower_bound = lower_bound;
  e.identified = identified;
  e.decided_by = identified ? "bobyqa + reduced" : "PHYSICS 7 bound";
  e.note = identified ? "CI from the profile likelihood" : "steady state not reached";
  return e;
}

inverse::Profile MakeProfile(int parameter, const SampledProfile& p, double s2, bool flat) {
  inverse::Profile profile;
  profile.parameter = parameter;
  for (std::size_t i = 0; i < p.value.size(); ++i)
    profile.points.push_back({p.value[i], p.chi2[i], true, {}});
  profile.chi2_threshold = 3.84 * s2;
  profile.flat = flat;
  return profile;
}

// A fit file written by the fit file's own writer (pipeline::WriteFitFile,
// the layout of `bridgefit fit --out`, docs/FORMATS.md) from a run shaped
// like the MDF sample's load fit (chi^2 about 665, reduced chi^2 1.6):
// sigma_c 0.45 MPa identified from its profile, delta_c >= 1.5 mm, J_B >= 340
// J/m^2 (its profile open above), J_tip,c 2210 J/m^2 from its profile. The
// report reads it with pipeline::ReadFitView: writer and reader tested together.
fs::path WriteFitFile(const fs::path& dir, bool with_record = false, bool load_fit = false,
                      bool jb_open = false) {
  const fs::path path = dir / "fit.h5";
  pipeline::FitRequest request;
  pipeline::FitRun run;
  if (with_record) {
    // Linear loading then growth: 30 rows of load, displacement, crack length.
    ExperimentRecord record;
    for (int i = 0; i < 30; ++i) {
      record.displacement.push_back(1e-4 * i);
      record.load.push_back(i < 10 ? 100.0 * i : 1000.0 - 20.0 * (i - 10));
      record.crack_length.push_back(i < 10 ? 0.030 : 0.030 + 0.001 * (i - 10));
    }
    run.input.record = record;
  }
  std::vector<double> a, R, fa, fR;
  for (int i = 0; i < 30; ++i) {
    a.push_back(0.030 + 0.04 * i / 29.0);
    R.push_back(2210 + 400 * (1 - std::exp(-i / 8.0)) + 10 * std::sin(i));
    fa.push_back(a.back());
    fR.push_back(2210 + 400 * (1 - std::exp(-i / 8.0)));
  }
  run.input.label = "rcurve.csv";
  run.input.curve.method = "energy";
  run.input.curve.crack_length = a;
  run.input.curve.R = R;
  run.data.crack_length = a;
  run.data.R = R;
  const double s2 = 1.6, chi2_min = 665.0;
  const SampledProfile sigma = SampleProfile(0.45e6, 0.0102e6, chi2_min, s2);
  const SampledProfile jtip = SampleProfile(2210, 10.2, chi2_min, s2);
  const SampledProfile jb = SampleProfile(450, 60, chi2_min, s2, true, 5000);
  inverse::FitSummary& f = run.summary;
  f.model = "reduced";
  f.optimizer = "ceres-lm";
  f.law = "linear";
  f.verdict = "sigma_c identified; J_B and delta_c are lower bounds";
  f.converged = true;
  f.steady_state_reached = false;
  f.bridging_detected = true;
  f.rms_residual = 7.0;
  f.reduced_chi2 = s2;
  f.wall_s = 1.5;
  f.fitted_crack_length = fa;
  f.fitted_R = fR;
  f.sigma_c = Estimate(0.45e6, sigma.low, sigma.high, NAN, true);
  f.delta_c = Estimate(2.0e-3, NAN, NAN, 1.5e-3, false);
  if (jb_open) {  // steady state reached, J_B's profile flat above: an open interval
    f.J_B = Estimate(450, jb.low, NAN, NAN, false);
    f.J_B.note = "profile likelihood flat above the optimum (0.5 .. 5000)";
  } else {
    f.J_B = Estimate(450, NAN, NAN, 340, false);
  }
  f.J_tip_c = Estimate(2210, jtip.low, jtip.high, NAN, true);
  f.profiles = {MakeProfile(inverse::kSigmaC, sigma, s2, false),
                MakeProfile(inverse::kJB, jb, s2, true),
                MakeProfile(inverse::kJTipC, jtip, s2, false)};
  if (load_fit) {
    f.target = inverse::FitTarget::kLoad;
    f.rms_residual = 3.0;
    f.fitted_displacement = {1e-4, 2e-4, 3e-4};
    f.fitted_record_load = {100, 200, 290};
    f.fitted_load = {101, 199, 292};
    run.load_data = run.data;
    run.load_fit_R = fR;
    run.load_fit_R_rms = 7.0;
  }
  pipeline::WriteFitFile(path.string(), request, run);
  return path;
}

}  // namespace

TEST(Report, PageFiguresAndTableWithUnits) {
  const fs::path dir = TempDir("page");
  const fs::path fit = WriteFitFile(dir);
  const report::ReportSummary s = pipeline::WriteFitReport(fit, dir / "report");
  ASSERT_TRUE(fs::exists(dir / "report" / "index.html"));
  EXPECT_EQ(s.index_html, fs::absolute(dir / "report" / "index.html").lexically_normal());
  const std::string html = ReadText(s.index_html);
  const auto sources = ImageSources(html);
  // R curve, law, profiles (no record given: no load-displacement figure).
  EXPECT_EQ(sources.size(), 3u);
  for (const std::string& src : sources) {
    const auto [w, h] = PngSize(dir / "report" / src);
    EXPECT_GT(w, 100) << src;
    EXPECT_GT(h, 100) << src;
  }
  // Table rows carry their units and the verdict is on the page.
  EXPECT_NE(html.find("<td>MPa</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>mm</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>J/m<sup>2</sup></td>"), std::string::npos);
  EXPECT_NE(html.find("J_B and delta_c are lower bounds"), std::string::npos);
  EXPECT_NE(html.find("lower bound only"), std::string::npos);
  EXPECT_NE(html.find("&ge; 1.5"), std::string::npos);  // delta_c bound in mm
  EXPECT_NE(html.find("<td>0.45</td>"), std::string::npos);  // sigma_c in MPa
  fs::remove_all(dir);
}

// The profile figure agrees with the printed table: the threshold drawn is
// the Delta chi^2 that defines the intervals (3.84 s^2 with s^2 = 1.6), and
// each printed end lies where the drawn profile crosses it.
TEST(Report, ProfileFigureShowsThePrintedIntervals) {
  const fs::path dir = TempDir("profiles");
  const fs::path fit = WriteFitFile(dir);
  pipeline::WriteFitReport(fit, dir / "report");
  const report_check::ProfileReadBack check = report_check::CheckProfileFigures(dir / "report", fit);
  EXPECT_EQ(check.profiles, 3);
  EXPECT_EQ(check.ends_checked, 4);  // sigma_c and J_tip,c, both ends
  for (const std::string& failure : check.failures) ADD_FAILURE() << failure;
  fs::remove_all(dir);
}

TEST(Report, RecordInTheFitFileGivesLoadAndCrackFigures) {
  const fs::path dir = TempDir("record");
  const report::ReportSummary s = pipeline::WriteFitReport(WriteFitFile(dir, true), dir / "report");
  const auto sources = ImageSources(ReadText(s.index_html));
  EXPECT_EQ(sources.size(), 5u);
  for (const char* fig : {"load_displacement.png", "crack_length.png"}) {
    EXPECT_NE(std::find(sources.begin(), sources.end(), fig), sources.end()) << fig;
    EXPECT_GT(PngSize(dir / "report" / fig).first, 100) << fig;
  }
  // The plotted table is the record in mm and N.
  std::ifstream in(dir / "report" / "record.dat");
  std::string header;
  std::getline(in, header);
  int frame;
  double d, p, a;
  int rows = 0;
  while (in >> frame >> d >> p >> a) {
    EXPECT_NEAR(d, 0.1 * frame, 1e-9);
    EXPECT_NEAR(a, frame < 10 ? 30.0 : 30.0 + (frame - 10), 1e-9);
    ++rows;
  }
  EXPECT_EQ(rows, 30);
  fs::remove_all(dir);
}

TEST(Report, LawRegionFollowsTheBounds) {
  // Linear laws with sigma_c in its CI (about [0.43, 0.47] MPa) and delta_c >=
  // 1.5 mm: the lowest is s_lo (1 - d/1.5 mm), the highest stays at s_hi
  // (delta_c unbounded).
  const fs::path dir = TempDir("law");
  const fs::path fit = WriteFitFile(dir);
  const io::H5Reader h5(fit);
  const double s_lo = h5.ReadNumberAttribute("/fit/parameters/sigma_c", "ci95_low") * 1e-6;
  const double s_hi = h5.ReadNumberAttribute("/fit/parameters/sigma_c", "ci95_high") * 1e-6;
  EXPECT_NEAR(s_lo, 0.43, 0.001);
  EXPECT_NEAR(s_hi, 0.47, 0.001);
  pipeline::WriteFitReport(fit, dir / "report");
  std::ifstream in(dir / "report" / "law.dat");
  std::string line;
  std::getline(in, line);
  int rows = 0;
  double d, lo, hi, best;
  std::string truth_text;
  while (in >> d >> lo >> hi >> best >> truth_text) {
    const double expected_lo = d < 1.5 ? s_lo * (1 - d / 1.5) : 0.0;
    const double expected_best = d < 2.0 ? 0.45 * (1 - d / 2.0) : 0.0;
    EXPECT_NEAR(lo, expected_lo, 1e-6) << d;
    EXPECT_NEAR(hi, s_hi, 1e-6) << d;
    EXPECT_NEAR(best, expected_best, 1e-6) << d;
    ++rows;
  }
  EXPECT_GT(rows, 100);
  fs::remove_all(dir);
}

// `report --lawfree`: the law-free curve and its band (lower clipped at 0)
// written in mm and MPa next to the law figure and plotted over it.
TEST(Report, LawFreeCurveDrawnOverTheFittedLaw) {
  const fs::path dir = TempDir("lawfree");
  const fs::path fit = WriteFitFile(dir);
  pipeline::LawFreeRun run;
  run.dic_file = "dic.h5";
  run.frames = 12;
  laws::LawFreeResult r;
  for (int j = 0; j <= 10; ++j) {
    const double d = 0.3e-3 * j / 10;
    r.delta.push_back(d);
    r.sigma.push_back(0.45e6 * (1 - d / 2e-3));
    r.sigma_standard_error.push_back(0.05e6);
    // Nodes 0-4 pinned (band +-0.02 MPa, within 10 % of the 0.45 MPa peak:
    // resolved, drawn thick); the rest wide, the lower end negative (drawn from 0).
    const bool pinned = j <= 4;
    r.sigma_lower.push_back(r.sigma.back() - (pinned ? 0.02e6 : 0.5e6));
    r.sigma_upper.push_back(r.sigma.back() + (pinned ? 0.02e6 : 0.1e6));
  }
  laws::MarkResolved(0.10, r);
  run.far_field = r;
  pipeline::WriteLawFreeH5(dir / "lawfree.h5", run);
  report::ReportOptions options;
  options.lawfree_h5 = dir / "lawfree.h5";
  const report::ReportSummary s = pipeline::WriteFitReport(fit, dir / "report", options);
  EXPECT_TRUE(std::find(s.figures.begin(), s.figures.end(), "law.png") != s.figures.end());
  std::ifstream in(dir / "report" / "lawfree_0.dat");
  std::string line;
  std::getline(in, line);
  EXPECT_NE(line.find("delta[mm] sigma[MPa] lower[MPa] upper[MPa] resolved_sigma[MPa]"),
            std::string::npos)
      << line;
  int rows = 0;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string d, sigma, lo, hi, pinned;
    ASSERT_TRUE(row >> d >> sigma >> lo >> hi >> pinned) << line;
    EXPECT_NEAR(std::stod(d), r.delta[rows] * 1e3, 1e-9);
    EXPECT_NEAR(std::stod(sigma), r.sigma[rows] * 1e-6, 1e-7);
    EXPECT_NEAR(std::stod(lo), rows <= 4 ? r.sigma_lower[rows] * 1e-6 : 0.0, 1e-7);
    EXPECT_NEAR(std::stod(hi), r.sigma_upper[rows] * 1e-6, 1e-7);
    if (rows <= 4)
      EXPECT_NEAR(std::stod(pinned), r.sigma[rows] * 1e-6, 1e-7) << line;
    else
      EXPECT_EQ(pinned, "NaN") << line;
    ++rows;
  }
  EXPECT_EQ(rows, 11);
  std::ifstream gp(dir / "report" / "report.gp");
  std::stringstream text;
  text << gp.rdbuf();
  EXPECT_NE(text.str().find("'lawfree_0.dat' u 1:2 w l"), std::string::npos);
  EXPECT_NE(text.str().find("'lawfree_0.dat' u 1:5 w l lw 5"), std::string::npos);
  EXPECT_NE(text.str().find("'lawfree_0.dat' u 1:3:4 w filledcurves"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Report, FailedGnuplotLeavesTheOldReport) {
  const fs::path dir = TempDir("atomic");
  const fs::path fit = WriteFitFile(dir);
  fs::create_directories(dir / "report");
  std::ofstream(dir / "report" / "index.html") << "old";
  report::ReportOptions options;
  options.gnuplot = "false";  // exits 1
  EXPECT_THROW(pipeline::WriteFitReport(fit, dir / "report", options), Error);
  EXPECT_EQ(ReadText(dir / "report" / "index.html"), "old");
  int leftovers = 0;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) ++leftovers;
  EXPECT_EQ(leftovers, 0);
  fs::remove_all(dir);
}

TEST(Report, MissingFitFileIsAnInputError) {
  try {
    pipeline::WriteFitReport("/nonexistent/fit.h5", TempDir("missing") / "r");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    EXPECT_EQ(e.context().file, "/nonexistent/fit.h5");
  }
}

TEST(ReportBrowser, HeadlessChromiumLoadsEveryFigure) {
  const std::string chromium = FindChromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium not installed: install it (BRIDGEFIT_EXTRA_PACKAGES=chromium bash "
                    "scripts/setup.sh, or apt-get install chromium) to run the browser check";
  const fs::path dir = TempDir("browser");
  pipeline::WriteFitReport(WriteFitFile(dir), dir / "report");
  const fs::path page = dir / "report" / "index.html";
  EXPECT_EQ(CheckStatus(DumpDom(chromium, page, dir)), "ok");

  // The check can fail: a missing figure and a script error are both seen.
  fs::remove(dir / "report" / "law.png");
  EXPECT_EQ(CheckStatus(DumpDom(chromium, page, dir)), "missing-images");
  std::string html = ReadText(page);
  html.replace(html.find("</body>"), 7, "<script>undefined_function();</script></body>");
  std::ofstream(dir / "report" / "broken.html") << html;
  EXPECT_EQ(CheckStatus(DumpDom(chromium, dir / "report" / "broken.html", dir)), "script-error");
  fs::remove_all(dir);
}

// The read-back on any report: BRIDGEFIT_REPORT_CHECK=DIR:FIT.h5 (e.g. a demo
// report, out/mdf_ct:out/mdf_ct.work/fit.h5); skipped when unset.
TEST(ReportReadBack, ReportNamedInTheEnvironment) {
  const char* spec = std::getenv("BRIDGEFIT_REPORT_CHECK");
  if (!spec) GTEST_SKIP() << "set BRIDGEFIT_REPORT_CHECK=REPORT_DIR:FIT_H5 to check a report";
  const std::string text(spec);
  const size_t colon = text.find(':');
  ASSERT_NE(colon, std::string::npos) << text;
  const report_check::ProfileReadBack check =
      report_check::CheckProfileFigures(text.substr(0, colon), text.substr(colon + 1));
  std::cout << check.profiles << " profiles, " << check.ends_checked << " printed ends checked\n";
  EXPECT_GT(check.profiles, 0);
  for (const std::string& failure : check.failures) ADD_FAILURE() << failure;
}

// DIC evidence from a DIC file in the layout of `bridgefit dic --out` with
// three 80x50 frames: the reference, a flagged middle frame (half of its
// points correlated) and the last are drawn with the tips and the window;
// the frame table links them; a crack-path dataset (a later DIC version)
// is drawn when present; the opening figure reads the profiles.
TEST(Report, DicEvidenceFromTheDicFile) {
  const fs::path dir = TempDir("dic");
  const fs::path fit = WriteFitFile(dir, true);
  fs::create_directories(dir / "images");
  for (int k = 0; k < 3; ++k) {
    dic::Image image(80, 50);
    for (int y = 0; y < 50; ++y)
      for (int x = 0; x < 80; ++x) image.at(x, y) = static_cast<float>((x * 7 + y * 13 + k * 5) % 256);
    dic::WriteImage(dir / "images" / ("f" + std::to_string(k) + ".png"), image, 8);
  }
  {
    io::H5Writer h5(dir / "dic.h5");
    // Recorded as bare names: resolved through --images.
    h5.WriteStrings("/dic/images", {"f0.png", "f1.png", "f2.png"});
    h5.WriteStrings("/dic/tip_method", {"none", "williams", "williams"});
    h5.WriteVector("/dic/crack_length", {NAN, 0.0220, 0.0230}, "m");
    h5.WriteVector("/dic/tip_x", {NAN, 20.0, 30.0}, "px");
    h5.WriteVector("/dic/tip_y", {NAN, 25.0, 25.0}, "px");
    h5.WriteVector("/dic/valid_fraction", {1.0, 0.5, 0.95}, "1");
    h5.WriteAttribute("/dic", "crack_line_px", "0,25,79,25");
    h5.WriteAttribute("/dic", "scale_m_per_px", 1e-4);
    h5.WriteAttribute("/dic", "offset_m", 0.020);
    h5.WriteAttribute("/dic", "fit_radius_px", 12.0);
    for (int k = 1; k < 3; ++k) {
      const std::string g = "/dic/frame_000" + std::to_string(k);
      h5.WriteVector(g + "/cod_s", {0, 10, 20, 30, 40}, "px");
      h5.WriteVector(g + "/cod_opening", {0.5 * k, 0.3 * k, 0.1 * k, 0.0, 0.0}, "px");
    }
    h5.WriteVector("/dic/frame_0002/path_x", {0, 15, 30}, "px");
    h5.WriteVector("/dic/frame_0002/path_y", {25, 26, 25}, "px");
    h5.Commit();
  }
  report::ReportOptions options;
  options.dic_h5 = dir / "dic.h5";
  options.images_dir = dir / "images";
  const report::ReportSummary s = pipeline::WriteFitReport(fit, dir / "report", options);
  const std::string html = ReadText(s.index_html);
  const auto sources = ImageSources(html);
  for (const char* fig : {"dic_frame_0000.png", "dic_frame_0001.png", "dic_frame_0002.png", "dic_opening.png"}) {
    EXPECT_NE(std::find(sources.begin(), sources.end(), fig), sources.end()) << fig;
    EXPECT_GT(PngSize(dir / "report" / fig).first, 100) << fig;
  }
  EXPECT_NE(html.find("href=\"#dic_frame_0001\""), std::string::npos);
  EXPECT_NE(html.find("<figure id=\"dic_frame_0001\">"), std::string::npos);
  EXPECT_NE(html.find("50% of the points correlated"), std::string::npos);  // the flag, said
  // The tips drawn are the file's, with their frame and crack length in mm.
  std::ifstream tips(dir / "report" / "dic_tips.dat");
  std::string line;
  std::getline(tips, line);
  double x, y, a;
  int frame;
  std::vector<int> frames;
  while (tips >> x >> y >> frame >> a) {
    EXPECT_EQ(x, frame == 1 ? 20.0 : 30.0);
    EXPECT_EQ(y, 25.0);
    EXPECT_NEAR(a, frame == 1 ? 22.0 : 23.0, 1e-9);
    frames.push_back(frame);
  }
  EXPECT_EQ(frames, (std::vector<int>{1, 2}));
  EXPECT_TRUE(fs::exists(dir / "report" / "dic_frame_0002_path.dat"));
  // The opening in um at a in mm: 0.5 px x 0.1 mm/px = 50 um at a = 20 mm (frame 1).
  std::ifstream opening(dir / "report" / "dic_opening_0001.dat");
  std::getline(opening, line);
  double at, open;
  opening >> at >> open;
  EXPECT_NEAR(at, 20.0, 1e-9);
  EXPECT_NEAR(open, 50.0, 1e-9);

  // Images that cannot be found: the frames are not drawn, the page says why.
  options.images_dir = dir / "nowhere";
  fs::rename(dir / "images", dir / "moved");
  const report::ReportSummary without = pipeline::WriteFitReport(fit, dir / "report2", options);
  const std::string html2 = ReadText(without.index_html);
  EXPECT_EQ(html2.find("dic_frame_0000.png\""), std::string::npos);
  EXPECT_NE(html2.find("3 of 3 DIC images not found"), std::string::npos);
  fs::remove_all(dir);
}

// Every multiplot panel sets its four margins in screen coordinates and no two
// panels of one figure come closer than 5% of the canvas (room for the tick
// labels between them): the stacked R-curve and load panels, the profiles.
TEST(Report, MultiplotPanelsHaveExplicitSeparatedMargins) {
  const fs::path dir = TempDir("margins");
  const fs::path fit = WriteFitFile(dir, true, true);  // a load fit: its stacked figure too
  pipeline::WriteFitReport(fit, dir / "report");
  std::istringstream gp(ReadText(dir / "report" / "report.gp"));
  struct Box { double l, r, t, b; };
  std::vector<std::vector<Box>> figures;
  std::map<std::string, double> margin;
  bool inside = false;
  std::string line;
  const std::regex set_margin("set ([lrtb])margin at screen ([-0-9.]+)");
  while (std::getline(gp, line)) {
    std::smatch m;
    if (line.rfind("set multiplot", 0) == 0) inside = true, figures.emplace_back(), margin.clear();
    if (line.rfind("unset multiplot", 0) == 0) inside = false;
    if (!inside) continue;
    if (std::regex_search(line, m, set_margin)) margin[m[1]] = std::stod(m[2]);
    if (line.rfind("plot ", 0) == 0) {
      ASSERT_EQ(margin.size(), 4u) << "panel without four screen margins: " << line;
      figures.back().push_back({margin["l"], margin["r"], margin["t"], margin["b"]});
    }
  }
  ASSERT_EQ(figures.size(), 3u);  // R curve, profiles, load-displacement
  for (const auto& panels : figures) {
    ASSERT_GE(panels.size(), 2u);
    for (size_t i = 0; i < panels.size(); ++i)
      for (size_t j = i + 1; j < panels.size(); ++j) {
        const Box& a = panels[i];
        const Box& b = panels[j];
        const double gap = std::max({b.l - a.r, a.l - b.r, a.b - b.t, b.b - a.t});
        EXPECT_GE(gap, 0.05) << "panels " << i << " and " << j;
      }
  }
  fs::remove_all(dir);
}

// An open-ended profile: J_B flat above its optimum. Its printed lower end is
// on the profile at the threshold, the upper side is labelled open and no
// upper end is marked.
TEST(Report, OpenEndedProfileDrawnOpen) {
  const fs::path dir = TempDir("open");
  const fs::path fit = WriteFitFile(dir, false, false, true);
  pipeline::WriteFitReport(fit, dir / "report");
  const report_check::ProfileReadBack check = report_check::CheckProfileFigures(dir / "report", fit);
  EXPECT_EQ(check.ends_checked, 5);  // sigma_c and J_tip,c both ends, J_B the lower
  for (const std::string& failure : check.failures) ADD_FAILURE() << failure;
  std::ifstream ends(dir / "report" / "profile_J_B_ends.dat");
  std::string header;
  std::getline(ends, header);
  double value, delta;
  std::vector<double> marked;
  while (ends >> value >> delta)
    if (std::isfinite(value)) marked.push_back(value);
  ASSERT_EQ(marked.size(), 1u);
  EXPECT_LT(marked[0], 450.0);
  const std::string gp = ReadText(dir / "report" / "report.gp");
  EXPECT_NE(gp.find("open: under the threshold"), std::string::npos);
  EXPECT_NE(ReadText(dir / "report" / "index.html").find("(open above)"), std::string::npos);
  fs::remove_all(dir);
}
