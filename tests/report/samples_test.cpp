// The bundled samples end to end through the CLI (BRIDGEFIT_CLI):
// (images -> bridgefit dic ->) record -> bridgefit rcurve -> bridgefit fit ->
// bridgefit report, checking
// the expected outcome written in each sample's README:
//   mdf_ct: sigma_c within 5% of the true 0.45 MPa; J_B and delta_c lower bounds
//           (noisy record fitted as load-displacement, exact record as an R curve);
//   pb_ct: no bridging detected;  dcb_composite: a converged fit.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "figure_check.hpp"

namespace fs = std::filesystem;
using namespace bridgefit;

namespace {

const fs::path kSamples = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples";

std::string ReadText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `bridgefit <args>`; returns the exit code, stdout in `out`.
int Cli(const std::string& args, const fs::path& work, std::string* out) {
  const fs::path so = work / "stdout.txt", se = work / "stderr.txt";
  const std::string cmd = std::string("'") + BRIDGEFIT_CLI + "' " + args + " > '" + so.string() +
                          "' 2> '" + se.string() + "'";
  const int status = std::system(cmd.c_str());
  *out = ReadText(so);
  const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (rc != 0) ADD_FAILURE() << "bridgefit " << args << " -> " << rc << "\n" << ReadText(se);
  return rc;
}

struct Chain {
  nlohmann::json fit;
  fs::path report, fit_h5;
  bool with_dic = false;
};

// (dic ->) rcurve -> fit -> report for one sample; `record_args` reads its
// record. With `with_dic` the crack lengths come from DIC on the sample's
// images (as in scripts/demo.sh), matched by the record's image column.
Chain RunChain(const std::string& sample, std::string record_args, const std::string& fit_args,
               bool with_dic = false, const std::string& reference_args = "") {
  static int chains = 0;  // one folder per chain (a test may run two)
  const fs::path work = fs::temp_directory_path() / ("bf_samples_" + sample + "_" + std::to_string(::getpid()) +
                                                     "_" + std::to_string(++chains));
  fs::remove_all(work);
  fs::create_directories(work);
  const fs::path scene = kSamples / sample / "scene.toml";
  std::string out;
  Chain chain;
  std::string report_args = reference_args;
  chain.with_dic = with_dic;
  if (with_dic) {
    const fs::path dic = work / "dic.csv", dic_h5 = work / "dic.h5";
    if (Cli("dic '" + (kSamples / sample / "images").string() +
                "' --crack-line 0,150,399,150 --scale 0.15mm/px --offset 20mm --csv '" + dic.string() +
                "' --out '" + dic_h5.string() + "' --quiet",
            work, &out) != 0)
      return chain;
    record_args += " --crack-length-from '" + dic.string() + "'";
    report_args += " --dic '" + dic.string() + "' --dic '" + dic_h5.string() + "'";
  }
  if (Cli("rcurve " + record_args + " --scene '" + scene.string() + "' --method energy --out '" +
              (work / "rcurve.h5").string() + "' --quiet",
          work, &out) != 0)
    return chain;
  if (Cli("fit '" + (work / "rcurve.h5").string() + "' --scene '" + scene.string() + "' " + fit_args +
              " --out '" + (work / "fit.h5").string() + "' --json --quiet",
          work, &out) != 0 && out.empty())
    return chain;
  chain.fit = nlohmann::json::parse(out, nullptr, false);
  chain.report = work / "report";
  chain.fit_h5 = work / "fit.h5";
  Cli("report '" + (work / "fit.h5").string() + "' --out '" + chain.report.string() + "' --record '" +
          (work / "rcurve.h5").string() + "' --truth '" + scene.string() + "' --quiet" + report_args,
      work, &out);
  return chain;
}

// The page: every expected figure is on it and decodes in headless Chromium
// (skipped with a message without Chromium); the DIC evidence figures (the
// reference and last frame with the overlays, the opening profiles) when the
// chain ran DIC on images; the profile figure agrees with the printed table.
void ExpectReport(const Chain& chain, std::vector<std::string> figures) {
  const std::string html = ReadText(chain.report / "index.html");
  EXPECT_NE(html.find("Identifiability verdict"), std::string::npos);
  const std::vector<std::string> sources = report_check::ImageSources(html);
  if (chain.with_dic) {
    int overlays = 0;
    for (const std::string& src : sources) overlays += src.rfind("dic_frame_", 0) == 0;
    EXPECT_GE(overlays, 2) << "reference and last frame with the crack line, tips and window";
    EXPECT_TRUE(fs::exists(chain.report / "dic_frame_0000.png"));
    figures.push_back("dic_opening.png");
    // The frame table links to the frames drawn.
    EXPECT_NE(html.find("href=\"#dic_frame_0000\""), std::string::npos);
  }
  for (const std::string& fig : figures) {
    EXPECT_NE(std::find(sources.begin(), sources.end(), fig), sources.end()) << fig << " not on the page";
  }
  for (const std::string& src : sources)
    EXPECT_GT(report_check::PngSize(chain.report / src).first, 100) << src;
  const report_check::ProfileReadBack check = report_check::CheckProfileFigures(chain.report, chain.fit_h5);
  for (const std::string& failure : check.failures) ADD_FAILURE() << failure;
  const std::string chromium = report_check::FindChromium();
  if (chromium.empty()) {
    std::cout << "chromium not installed: browser check of " << chain.report << " skipped\n";
    return;
  }
  const std::string dom = report_check::DumpDom(chromium, chain.report / "index.html", chain.report.parent_path());
  EXPECT_EQ(report_check::CheckStatus(dom), "ok") << chain.report;
}

}  // namespace

// The MDF test's expected outcome (sigma_c within 5% of 0.45 MPa, J_B and
// delta_c lower bounds below the truth) from a fit `c`.
void ExpectMdfOutcome(const Chain& c) {
  ASSERT_TRUE(c.fit.is_object());
  const double sigma_c = c.fit["sigma_c_Pa"]["value"].get<double>();
  EXPECT_NEAR(sigma_c, 0.45e6, 0.05 * 0.45e6);
  EXPECT_TRUE(c.fit["bridging_detected"].get<bool>());
  EXPECT_FALSE(c.fit["steady_state_reached"].get<bool>());
  for (const char* key : {"J_B_J_per_m2", "delta_c_m"}) {
    EXPECT_FALSE(c.fit[key]["identified"].get<bool>()) << key;
    ASSERT_TRUE(c.fit[key]["lower_bound"].is_number()) << key;
  }
  // The bounds are consistent with the truth: J_B = 500 J/m^2, delta_c = 2 J_B / sigma_c.
  EXPECT_LE(c.fit["J_B_J_per_m2"]["lower_bound"].get<double>(), 500.0);
  EXPECT_LE(c.fit["delta_c_m"]["lower_bound"].get<double>(), 2 * 500.0 / 0.45e6);
}

// The demo's route: crack lengths from DIC on the 10 frames, the noisy record
// (0.5% load, 1 um displacement), its R curve for the start, the fit to its
// load-displacement rows.
TEST(Samples, MdfNoisyRecordSigmaCWithinFivePercentAndLowerBounds) {
  const fs::path record = kSamples / "mdf_ct" / "record.csv";
  ASSERT_TRUE(fs::exists(record)) << "run scripts/make_samples.sh";
  const Chain c = RunChain("mdf_ct", "'" + record.string() + "' --smooth 30",
                           "--fit-to load-displacement --law linear --resolution 1mm", true);
  ExpectMdfOutcome(c);
  ExpectReport(c, {"rcurve.png", "law.png", "profiles.png", "load_displacement.png", "crack_length.png"});
  EXPECT_EQ(c.fit["fit_to"], "load-displacement");
  EXPECT_TRUE(fs::exists(c.report / "load_fit.dat"));
  // DIC's crack lengths drawn at the rows of their images (the record's image column).
  EXPECT_EQ(ReadText(c.report / "dic.dat").rfind("# record_row", 0), 0u);
}

// The R-curve route on the noise-free record (with the noisy one the bridging
// rise is below the energy method's resolution); tiny declared noise for the weights.
TEST(Samples, MdfExactRecordRCurveSigmaCWithinFivePercent) {
  const fs::path record = kSamples / "mdf_ct" / "record_exact.csv";
  ASSERT_TRUE(fs::exists(record)) << "run scripts/make_samples.sh";
  const Chain c = RunChain("mdf_ct",
                           "'" + record.string() +
                               "' --load-noise 0.01N --displacement-noise 0.01um --crack-noise 0.001mm",
                           "--law linear --resolution 1mm");
  ExpectMdfOutcome(c);
  ExpectReport(c, {"rcurve.png", "law.png", "profiles.png", "load_displacement.png", "crack_length.png"});
}

// The demo's route (DIC, load-displacement fit) and the R curve of the
// record's own crack-length column.
TEST(Samples, ParticleBoardHasNoBridging) {
  const fs::path record = kSamples / "pb_ct" / "record.csv";
  ASSERT_TRUE(fs::exists(record)) << "run scripts/make_samples.sh";
  const Chain demo = RunChain("pb_ct", "'" + record.string() + "' --smooth 30",
                              "--fit-to load-displacement --law linear --resolution 1mm", true);
  const Chain r_curve = RunChain("pb_ct", "'" + record.string() + "'", "--law linear --resolution 1mm");
  for (const Chain* c : {&demo, &r_curve}) {
    ASSERT_TRUE(c->fit.is_object());
    EXPECT_FALSE(c->fit["bridging_detected"].get<bool>()) << c->fit["verdict"];
    // R stays at J_tip,c = 1450 J/m^2 (5%).
    EXPECT_NEAR(c->fit["J_tip_c_J_per_m2"]["value"].get<double>(), 1450.0, 0.05 * 1450.0);
    // No bridging: no law figure.
    ExpectReport(*c, {"rcurve.png", "profiles.png", "load_displacement.png", "crack_length.png"});
  }
}

TEST(Samples, DcbCompositeConvergedFit) {
  const fs::path record = kSamples / "dcb_composite" / "DCB-01_Toughness.csv";
  const Chain c = RunChain(
      "dcb_composite",
      "'" + record.string() +
          "' --columns time=Time,displacement=Disp,load=Force,crack_length=CrackExt "
          "--units time=s,displacement=mm,load=N,crack_length=mm",
      "--law linear --resolution 0.6mm", false,
      " --reference-csv '" + record.string() +
          "' --reference G_I --columns crack_length=CrackExt --units crack_length=mm,G_I=N/mm");
  ASSERT_TRUE(c.fit.is_object());
  EXPECT_TRUE(c.fit["converged"].get<bool>());
  EXPECT_TRUE(c.fit["sigma_c_Pa"]["value"].is_number());
  // The authors' G_I (N/mm) drawn against R, with its deviation in a table.
  ExpectReport(c, {"rcurve.png", "law.png", "profiles.png", "load_displacement.png", "crack_length.png",
                   "reference.png"});
  const std::string html = ReadText(c.report / "index.html");
  EXPECT_NE(html.find("id=\"reference\""), std::string::npos);
}
