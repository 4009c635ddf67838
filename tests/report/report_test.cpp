// Report: page, figures and table from a fit file with known content; the
// page checked in headless Chromium (skipped, with a message, when absent).
#include "bridgefit/report/report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace fs = std::filesystem;
using namespace bridgefit;

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

void WriteEstimate(io::H5Writer& f, const std::string& g, double value, double lo, double hi,
                   double lower_bound, bool identified, const std::string& units) {
  f.WriteAttribute(g, "units", units);
  f.WriteAttribute(g, "value", value);
  f.WriteAttribute(g, "ci95_low", lo);
  f.WriteAttribute(g, "ci95_high", hi);
  f.WriteAttribute(g, "lower_bound", lower_bound);
  f.WriteAttribute(g, "identified", identified ? 1.0 : 0.0);
  f.WriteAttribute(g, "fixed", 0.0);
  f.WriteAttribute(g, "decided_by", "profile");
  f.WriteAttribute(g, "note", identified ? "" : "steady state not reached");
}

// A fit file in the layout of `bridgefit fit --out` (docs/FORMATS.md):
// sigma_c identified in [0.43, 0.47] MPa, delta_c >= 1.5 mm, J_B >= 340 J/m^2.
fs::path WriteFitFile(const fs::path& dir, bool with_record = false) {
  const fs::path path = dir / "fit.h5";
  io::H5Writer f(path);
  if (with_record) {
    // Linear loading then growth: 30 rows of load, displacement, crack length.
    ExperimentRecord record;
    for (int i = 0; i < 30; ++i) {
      record.displacement.push_back(1e-4 * i);
      record.load.push_back(i < 10 ? 100.0 * i : 1000.0 - 20.0 * (i - 10));
      record.crack_length.push_back(i < 10 ? 0.030 : 0.030 + 0.001 * (i - 10));
    }
    io::WriteRecordH5(f, record, "/experiment");
  }
  std::vector<double> a, R, fa, fR;
  for (int i = 0; i < 30; ++i) {
    a.push_back(0.030 + 0.04 * i / 29.0);
    R.push_back(2210 + 400 * (1 - std::exp(-i / 8.0)) + 10 * std::sin(i));
    fa.push_back(a.back());
    fR.push_back(2210 + 400 * (1 - std::exp(-i / 8.0)));
  }
  const std::string g = "/fit";
  f.WriteAttribute(g, "model", "reduced");
  f.WriteAttribute(g, "optimizer", "ceres-lm");
  f.WriteAttribute(g, "law", "linear");
  f.WriteAttribute(g, "verdict", "sigma_c identified; J_B and delta_c are lower bounds");
  f.WriteAttribute(g, "converged", 1.0);
  f.WriteAttribute(g, "steady_state_reached", 0.0);
  f.WriteAttribute(g, "bridging_detected", 1.0);
  f.WriteAttribute(g, "rms_residual_J_per_m2", 7.0);
  f.WriteAttribute(g, "wall_s", 1.5);
  f.WriteVector(g + "/crack_length", a, "m");
  f.WriteVector(g + "/R", R, "J/m^2");
  f.WriteVector(g + "/fitted_crack_length", fa, "m");
  f.WriteVector(g + "/fitted_R", fR, "J/m^2");
  f.WriteVector(g + "/outlier_crack_length", {}, "m");
  f.WriteVector(g + "/outlier_R", {}, "J/m^2");
  WriteEstimate(f, g + "/parameters/sigma_c", 0.45e6, 0.43e6, 0.47e6, NAN, true, "Pa");
  WriteEstimate(f, g + "/parameters/delta_c", 2.0e-3, NAN, NAN, 1.5e-3, false, "m");
  WriteEstimate(f, g + "/parameters/J_B", 450, NAN, NAN, 340, false, "J/m^2");
  WriteEstimate(f, g + "/parameters/J_tip_c", 2210, 2190, 2230, NAN, true, "J/m^2");
  std::vector<double> pv, pc;
  for (int i = 0; i < 9; ++i) {
    pv.push_back(0.41e6 + 0.01e6 * i);
    pc.push_back(20 + std::pow((pv.back() - 0.45e6) / 0.01e6, 2) * 1.5);
  }
  f.WriteVector(g + "/profiles/sigma_c/value", pv, "Pa");
  f.WriteVector(g + "/profiles/sigma_c/chi2", pc, "1");
  f.WriteAttribute(g + "/profiles/sigma_c", "chi2_threshold", 23.84);
  f.Commit();
  return path;
}

std::vector<std::string> ImageSources(const std::string& html) {
  std::vector<std::string> out;
  const std::regex img("<img[^>]*src=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

// PNG width and height from the IHDR chunk (0 when not a PNG).
std::pair<int, int> PngSize(const fs::path& p) {
  const std::string s = ReadText(p);
  if (s.size() < 24 || s.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return {0, 0};
  auto be = [&](size_t o) {
    return (int(uint8_t(s[o])) << 24) | (int(uint8_t(s[o + 1])) << 16) |
           (int(uint8_t(s[o + 2])) << 8) | int(uint8_t(s[o + 3]));
  };
  return {be(16), be(20)};
}

std::string FindChromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const std::string cmd = std::string("command -v ") + name + " > /dev/null 2>&1";
    if (std::system(cmd.c_str()) == 0) return name;
  }
  return "";
}

// DOM after load, as headless Chromium sees it.
std::string DumpDom(const std::string& chromium, const fs::path& page, const fs::path& work) {
  const fs::path profile = work / "chromium-profile";
  const fs::path out = work / "dom.html";
  const std::string cmd = "timeout 60 " + chromium +
                          " --headless --no-sandbox --disable-gpu --disable-dev-shm-usage"
                          " --disable-background-networking --disable-component-update"
                          " --disable-sync --no-first-run --user-data-dir='" + profile.string() +
                          "' --dump-dom 'file://" + fs::absolute(page).string() + "' > '" +
                          out.string() + "' 2> '" + (work / "chromium.log").string() + "'";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << ReadText(work / "chromium.log");
  return ReadText(out);
}

std::string CheckStatus(const std::string& dom) {
  std::smatch m;
  if (std::regex_search(dom, m, std::regex("id=\"bf-check\"[^>]*data-status=\"([a-z-]+)\"")))
    return m[1];
  if (std::regex_search(dom, m, std::regex("data-status=\"([a-z-]+)\"[^>]*id=\"bf-check\"")))
    return m[1];
  return "absent";
}

}  // namespace

TEST(Report, PageFiguresAndTableWithUnits) {
  const fs::path dir = TempDir("page");
  const fs::path fit = WriteFitFile(dir);
  const report::ReportSummary s = report::WriteFitReport(fit, dir / "report");
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

TEST(Report, RecordInTheFitFileGivesLoadAndCrackFigures) {
  const fs::path dir = TempDir("record");
  const report::ReportSummary s = report::WriteFitReport(WriteFitFile(dir, true), dir / "report");
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
  // Linear laws with sigma_c in [0.43, 0.47] MPa and delta_c >= 1.5 mm: the
  // lowest is 0.43 (1 - d/1.5 mm), the highest stays at 0.47 MPa (delta_c unbounded).
  const fs::path dir = TempDir("law");
  report::WriteFitReport(WriteFitFile(dir), dir / "report");
  std::ifstream in(dir / "report" / "law.dat");
  std::string line;
  std::getline(in, line);
  int rows = 0;
  double d, lo, hi, best;
  std::string truth_text;
  while (in >> d >> lo >> hi >> best >> truth_text) {
    const double expected_lo = d < 1.5 ? 0.43 * (1 - d / 1.5) : 0.0;
    const double expected_best = d < 2.0 ? 0.45 * (1 - d / 2.0) : 0.0;
    EXPECT_NEAR(lo, expected_lo, 1e-6) << d;
    EXPECT_NEAR(hi, 0.47, 1e-6) << d;
    EXPECT_NEAR(best, expected_best, 1e-6) << d;
    ++rows;
  }
  EXPECT_GT(rows, 100);
  fs::remove_all(dir);
}

TEST(Report, FailedGnuplotLeavesTheOldReport) {
  const fs::path dir = TempDir("atomic");
  const fs::path fit = WriteFitFile(dir);
  fs::create_directories(dir / "report");
  std::ofstream(dir / "report" / "index.html") << "old";
  report::ReportOptions options;
  options.gnuplot = "false";  // exits 1
  EXPECT_THROW(report::WriteFitReport(fit, dir / "report", options), Error);
  EXPECT_EQ(ReadText(dir / "report" / "index.html"), "old");
  int leftovers = 0;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp-") != std::string::npos) ++leftovers;
  EXPECT_EQ(leftovers, 0);
  fs::remove_all(dir);
}

TEST(Report, MissingFitFileIsAnInputError) {
  try {
    report::WriteFitReport("/nonexistent/fit.h5", TempDir("missing") / "r");
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
  report::WriteFitReport(WriteFitFile(dir), dir / "report");
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
