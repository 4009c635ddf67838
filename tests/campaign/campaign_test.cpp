// Campaigns as a library (issue 19). Oracles: every manifest fault is found
// before any fit, naming the manifest line; the statistics against hand
// computation (mean, SD, CV, the largest bound, the modified z-score rule);
// a campaign of identical specimens gives each the single fit's result and
// zero scatter, and a specimen whose record cannot be read is reported
// failed while the others finish.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "../cli/cli_helpers.hpp"
#include "../report/figure_check.hpp"
#include "bridgefit/campaign/campaign.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/campaign_manifest.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"

namespace bridgefit::campaign {
namespace {

namespace fs = std::filesystem;
const fs::path kSample = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples" / "mdf_ct";

struct WorkDir {
  fs::path path = fs::temp_directory_path() / ("bf_campaign_" + std::to_string(::getpid()));
  WorkDir() {
    fs::remove_all(path);
    fs::create_directories(path);
    fs::copy_file(kSample / "scene.toml", path / "scene.toml");
    fs::copy_file(kSample / "record.csv", path / "a.csv");
  }
  ~WorkDir() { fs::remove_all(path); }
  fs::path Write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return path / name;
  }
};

std::string ErrorOf(const fs::path& manifest) {
  try {
    const io::CampaignManifest m = io::ReadCampaignManifest(manifest);
    BuildRequests(m);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << manifest;
  return "";
}

const char* const kHead =
    "[campaign]\n"                   // line 1
    "scene = \"scene.toml\"\n"       // 2
    "law = \"linear\"\n"             // 3
    "resolution = \"1 mm\"\n"        // 4
    "profile = false\n"              // 5
    "[[specimen]]\n"                 // 6
    "name = \"A\"\n"                 // 7
    "record = \"a.csv\"\n";          // 8

TEST(CampaignManifest, ReadsSharedChoicesAndSpecimenSizes) {
  WorkDir dir;
  const fs::path m = dir.Write("c.toml", std::string(kHead) +
                                             "[[specimen]]\nname = \"B\"\nrecord = \"a.csv\"\n"
                                             "notch = \"35 mm\"\nrcurve_method = \"lefm\"\n");
  const io::CampaignManifest manifest = io::ReadCampaignManifest(m);
  ASSERT_EQ(manifest.specimens.size(), 2u);
  EXPECT_EQ(manifest.name, "c");
  EXPECT_DOUBLE_EQ(*manifest.resolution, 1e-3);
  EXPECT_FALSE(manifest.profile);
  EXPECT_DOUBLE_EQ(manifest.specimens[0].scene.specimen.notch, 30e-3);  // the scene's
  EXPECT_DOUBLE_EQ(manifest.specimens[1].scene.specimen.notch, 35e-3);  // its own
  EXPECT_EQ(manifest.specimens[1].line, 9);
  const std::vector<pipeline::FitRequest> requests = BuildRequests(manifest);
  EXPECT_EQ(requests[0].reduction.method, experiment::RMethod::kEnergy);
  EXPECT_EQ(requests[1].reduction.method, experiment::RMethod::kLefm);
  EXPECT_DOUBLE_EQ(requests[1].resolution, 1e-3);
  EXPECT_FALSE(requests[1].fit.profile_likelihood);
}

// The manifest's `law` goes through fit's one rule (pipeline::SetFitLaw):
// a fitted-shape family alone, compare, a fixed family; an unknown law is
// found before any fit, naming the manifest's line and the values.
TEST(CampaignManifest, LawKeyIsFitsLawRule) {
  WorkDir dir;
  auto law = [&](const std::string& text) {
    std::string head = kHead;
    head.replace(head.find("\"linear\""), 8, "\"" + text + "\"");
    return dir.Write("law.toml", head);
  };
  pipeline::FitRequest r = BuildRequests(io::ReadCampaignManifest(law("table")))[0];
  ASSERT_TRUE(r.shape_law);
  EXPECT_EQ(*r.shape_law, inverse::ShapeFamily::kTable);
  EXPECT_FALSE(r.compare_laws);
  r = BuildRequests(io::ReadCampaignManifest(law("bilinear")))[0];
  ASSERT_TRUE(r.shape_law);
  EXPECT_EQ(*r.shape_law, inverse::ShapeFamily::kBilinear);
  r = BuildRequests(io::ReadCampaignManifest(law("compare")))[0];
  EXPECT_TRUE(r.compare_laws);
  EXPECT_FALSE(r.shape_law);
  r = BuildRequests(io::ReadCampaignManifest(law("cubic")))[0];
  EXPECT_FALSE(r.compare_laws || r.shape_law);
  EXPECT_EQ(r.law, laws::LawFamily::kCubic);
  const std::string m = ErrorOf(law("quadratic"));
  EXPECT_NE(m.find("law.toml:3"), std::string::npos) << m;
  EXPECT_NE(m.find("bilinear, trilinear or table"), std::string::npos) << m;
}

TEST(CampaignManifest, EachFaultIsFoundBeforeAnyFitNamingTheLine) {
  WorkDir dir;
  struct Case {
    std::string extra, what;
    int line;
  };
  const Case cases[] = {
      {"[[specimen]]\nname = \"B\"\nrecord = \"missing.csv\"\n", "file not found", 11},
      {"[[specimen]]\nname = \"A\"\nrecord = \"a.csv\"\n", "duplicate specimen name", 10},
      {"[[specimen]]\nname = \"B\"\nrecord = \"a.csv\"\ncolour = \"red\"\n", "unknown key", 12},
      {"[[specimen]]\nname = \"B\"\nrecord = \"a.csv\"\nnotch = 35\n", "a bare number needs a unit", 12},
      {"[[specimen]]\nname = \"B\"\nrecord = \"a.csv\"\nrcurve_method = \"magic\"\n", "unknown", 12},
  };
  for (const Case& c : cases) {
    const std::string m = ErrorOf(dir.Write("bad.toml", kHead + c.extra));
    EXPECT_NE(m.find("bad.toml:" + std::to_string(c.line)), std::string::npos) << m;
    EXPECT_NE(m.find(c.what), std::string::npos) << m;
  }
  // A campaign-level fault: an unknown top-level table.
  const std::string m = ErrorOf(dir.Write("bad2.toml", std::string(kHead) + "[extra]\nx = 1\n"));
  EXPECT_NE(m.find("bad2.toml:9"), std::string::npos) << m;
}

// [campaign] joint: the parameters the joint fit shares. Absent: all; a
// subset by name; an unknown name, delta_c (not a parameter of its own), a
// name twice, an empty list or a bare string are errors naming the line
// (6 here) and the allowed names - before any fit.
TEST(CampaignManifest, JointParametersAreCheckedNamingTheLine) {
  WorkDir dir;
  const auto with = [&](const std::string& name, const std::string& list) {
    std::string text = kHead;
    text.replace(text.find("profile = false\n"), 16, "profile = false\njoint = " + list + "\n");
    return io::ReadCampaignManifest(dir.Write(name, text));
  };
  EXPECT_EQ(JointSharedParameters(io::ReadCampaignManifest(dir.Write("all.toml", kHead))),
            inverse::kAllShared);
  EXPECT_EQ(JointSharedParameters(with("two.toml", "[\"J_B\", \"sigma_c\"]")),
            (inverse::SharedParameters{true, true, false}));
  struct Case {
    std::string list, what;
  };
  const Case cases[] = {{"[\"sigma_c\", \"G_c\"]", "unknown parameter"},
                        {"[]", "is empty"},
                        {"[\"delta_c\"]", "follows from J_B and sigma_c"},
                        {"[\"J_B\", \"J_B\"]", "named twice"}};
  for (const Case& c : cases) {
    std::string m;
    try {
      JointSharedParameters(with("bad.toml", c.list));
      ADD_FAILURE() << "no error for joint = " << c.list;
    } catch (const Error& e) {
      m = e.what();
    }
    EXPECT_NE(m.find("bad.toml:6"), std::string::npos) << m;
    EXPECT_NE(m.find(c.what), std::string::npos) << m;
    EXPECT_NE(m.find("sigma_c, J_B, J_tip_c"), std::string::npos) << m;
  }
  try {
    with("bare.toml", "\"sigma_c\"");
    ADD_FAILURE() << "a bare string was taken for a list";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bare.toml:6"), std::string::npos) << e.what();
  }
}

inverse::ParameterEstimate Value(double v) {
  inverse::ParameterEstimate e;
  e.value = v;
  e.identified = true;
  return e;
}
inverse::ParameterEstimate Bound(double b) {
  inverse::ParameterEstimate e;
  e.lower_bound = b;
  return e;
}

TEST(CampaignStatistics, MeanSdCvAndTheLargestBoundAgainstHandComputation) {
  const ParameterStatistics s =
      Summarise("J_B", "J/m^2", 1.0,
                {{"a", Value(400)}, {"b", Value(500)}, {"c", Bound(450)}, {"d", Bound(520)},
                 {"e", Value(600)}});
  EXPECT_EQ(s.values, 3);
  EXPECT_EQ(s.bounds, 2);
  EXPECT_DOUBLE_EQ(s.mean, 500.0);
  EXPECT_DOUBLE_EQ(s.sd, 100.0);  // sqrt((100^2 + 0 + 100^2) / 2)
  EXPECT_DOUBLE_EQ(s.cv, 0.2);
  EXPECT_DOUBLE_EQ(s.campaign_lower_bound, 520.0);
  EXPECT_EQ(s.bound_from, "d");
  EXPECT_TRUE(s.outliers.empty());
  EXPECT_NE(s.note.find("lower bound"), std::string::npos) << s.note;
}

TEST(CampaignStatistics, OutlierByModifiedZScoreIsFlaggedNotDropped) {
  // median 0.45, MAD 0.01: 0.6745 * 0.45 / 0.01 = 30 > 3.5 for 0.9; 0.47 gives 1.35.
  const ParameterStatistics s =
      Summarise("sigma_c", "MPa", 1e-6,
                {{"a", Value(0.44e6)}, {"b", Value(0.45e6)}, {"c", Value(0.46e6)},
                 {"d", Value(0.47e6)}, {"e", Value(0.90e6)}});
  ASSERT_EQ(s.outliers.size(), 1u);
  EXPECT_EQ(s.outliers[0], "e");
  EXPECT_EQ(s.values, 5);  // still counted
  EXPECT_NEAR(s.mean, 0.544e6, 1.0);
}

TEST(Campaign, IdenticalSpecimensGiveTheSingleFitAndAnUnreadableOneFailsAlone) {
  WorkDir dir;
  dir.Write("broken.csv", "time [s], load [N]\nnot, numbers\n");
  const fs::path m = dir.Write(
      "c.toml", std::string(kHead) + "[[specimen]]\nname = \"B\"\nrecord = \"a.csv\"\n" +
                    "[[specimen]]\nname = \"broken\"\nrecord = \"broken.csv\"\n");
  const io::CampaignManifest manifest = io::ReadCampaignManifest(m);
  CampaignOptions options;
  options.jobs = 2;
  int lines = 0;
  options.progress = [&lines](const std::string&) { ++lines; };
  options.joint = true;
  // sigma_c and J_B shared, J_tip,c each copy's own (as `campaign
  // --joint-parameters sigma_c,J_B` sets it, over the manifest).
  options.joint_parameters = inverse::SharedParameters{true, true, false};
  const CampaignResult r = RunCampaign(manifest, options);
  ASSERT_EQ(r.specimens.size(), 3u);
  EXPECT_EQ(lines, 7);  // started + finished, per specimen, and the joint fit
  EXPECT_EQ(r.Failed(), 1);
  EXPECT_FALSE(r.specimens[2].ran());
  EXPECT_NE(r.specimens[2].error.find("broken.csv"), std::string::npos) << r.specimens[2].error;
  ASSERT_TRUE(r.specimens[0].ok());
  ASSERT_TRUE(r.specimens[1].ok());

  // The single fit of the same request, outside the campaign.
  const pipeline::FitRun single = pipeline::RunFit(BuildRequests(manifest)[0]);
  const ParameterStatistics& jtip = r.statistics[3];
  EXPECT_EQ(jtip.parameter, "J_tip_c");
  EXPECT_DOUBLE_EQ(r.specimens[0].run->summary.J_tip_c.value, single.summary.J_tip_c.value);
  EXPECT_DOUBLE_EQ(r.specimens[1].run->summary.J_tip_c.value, single.summary.J_tip_c.value);
  EXPECT_EQ(jtip.values, 2);
  EXPECT_DOUBLE_EQ(jtip.mean, single.summary.J_tip_c.value);
  EXPECT_DOUBLE_EQ(jtip.sd, 0.0);

  // --joint on two copies of one record: one law describes them (the
  // likelihood ratio is about 0, on 2 x 1 dof: the joint optimum's chi^2 is
  // twice the single fit's), and each copy's own J_tip,c is the single fit's
  // at its optimum (this record shows no significant bridging at 1 mm: the
  // single fit reports the flat R curve's J_tip,c, its optimum is bridged).
  ASSERT_TRUE(r.joint.has_value()) << r.joint_error;
  EXPECT_EQ(r.joint->specimens, (std::vector<std::string>{"A", "B"}));
  EXPECT_TRUE(r.joint->consistency.consistent()) << r.joint->consistency.Summary();
  EXPECT_EQ(r.joint->consistency.degrees_of_freedom, 2);
  EXPECT_LT(r.joint->consistency.statistic, 0.01);
  ASSERT_EQ(r.joint->own_values.size(), 2u);
  const double tip = single.summary.best_parameters[inverse::kJTipC];
  for (const pipeline::OwnParameterValue& v : r.joint->own_values)
    EXPECT_NEAR(v.value, tip, 0.01 * tip);
  EXPECT_NE(r.BriefReport().find("joint fit of 2 specimens (A, B)"), std::string::npos);

  WriteCampaignOutputs(r, dir.path / "out");
  std::ifstream joint_csv(dir.path / "out" / "joint.csv");
  std::string joint_header, joint_first;
  std::getline(joint_csv, joint_header);
  std::getline(joint_csv, joint_first);
  EXPECT_NE(joint_header.find("p_value"), std::string::npos) << joint_header;
  EXPECT_NE(joint_header.find(",shared,carried_by"), std::string::npos) << joint_header;
  EXPECT_EQ(joint_first.rfind("sigma_c,MPa,", 0), 0u) << joint_first;
  std::ifstream own_csv(dir.path / "out" / "joint_own.csv");
  std::string own_header, own_a;
  std::getline(own_csv, own_header);
  std::getline(own_csv, own_a);
  EXPECT_EQ(own_a.rfind("A,J_tip_c,J/m^2,", 0), 0u) << own_a;
  EXPECT_TRUE(fs::exists(dir.path / "out" / "specimens" / "A.h5"));
  EXPECT_TRUE(fs::exists(dir.path / "out" / "specimens" / "B.h5"));
  EXPECT_FALSE(fs::exists(dir.path / "out" / "specimens" / "broken.h5"));
  std::ifstream summary(dir.path / "out" / "summary.csv");
  std::string header, a, b, broken;
  std::getline(summary, header);
  std::getline(summary, a);
  std::getline(summary, b);
  std::getline(summary, broken);
  EXPECT_NE(header.find("sigma_c [MPa]"), std::string::npos) << header;
  EXPECT_EQ(a.rfind("A,", 0), 0u) << a;
  EXPECT_EQ(broken.rfind("broken,failed,", 0), 0u) << broken;
  EXPECT_TRUE(fs::exists(dir.path / "out" / "statistics.csv"));

  // campaign.h5: each specimen's fit file under /specimens/<name> (the same
  // layout, read back by the fit file's own reader's paths), the statistics
  // and the joint fit under /campaign, in SI with units.
  const io::H5Reader h5(dir.path / "out" / "campaign.h5");
  EXPECT_TRUE(h5.Exists("/specimens/A/fit/parameters/J_tip_c"));
  EXPECT_TRUE(h5.Exists("/specimens/B/rcurve/R"));
  EXPECT_FALSE(h5.Exists("/specimens/broken"));
  EXPECT_EQ(h5.ReadStrings("/campaign/specimen_names"),
            (std::vector<std::string>{"A", "B", "broken"}));
  EXPECT_DOUBLE_EQ(h5.ReadNumberAttribute("/campaign/statistics/J_tip_c", "mean"), jtip.mean);
  EXPECT_EQ(h5.ReadStringAttribute("/campaign/statistics/J_tip_c", "units"), "J/m^2");
  std::string units;
  const std::vector<double> values = h5.ReadVector("/campaign/statistics/J_tip_c/value", &units);
  ASSERT_EQ(values.size(), 3u);
  EXPECT_DOUBLE_EQ(values[0], r.specimens[0].run->summary.J_tip_c.value);
  EXPECT_TRUE(std::isnan(values[2]));
  EXPECT_EQ(units, "J/m^2");
  EXPECT_EQ(h5.ReadNumberAttribute("/campaign/joint", "consistent"), 1.0);
  EXPECT_DOUBLE_EQ(h5.ReadNumberAttribute("/campaign/joint/parameters/J_B", "value"),
                   r.joint->summary.J_B.value);
  EXPECT_EQ(h5.ReadNumberAttribute("/campaign/joint/parameters/J_tip_c", "shared"), 0.0);
  EXPECT_EQ(h5.ReadStringAttribute("/campaign/joint", "shared_parameters"), "sigma_c, J_B");
  const std::vector<double> own_tip = h5.ReadVector("/campaign/joint/own/J_tip_c/value", &units);
  ASSERT_EQ(own_tip.size(), 2u);
  EXPECT_DOUBLE_EQ(own_tip[1], r.joint->own_values[1].value);
  EXPECT_EQ(units, "J/m^2");
  EXPECT_EQ(h5.ReadStrings("/campaign/joint/carriers/sigma_c/reasons").size(), 2u);

  // The campaign report: every R curve with its fit in one figure, the
  // specimen table (the failed one with its reason), statistics, joint fit.
  const fs::path report = dir.path / "out" / "report";
  ASSERT_TRUE(fs::exists(report / "index.html"));
  EXPECT_GT(fs::file_size(report / "rcurves.png"), 1000u);
  std::ifstream page_in(report / "index.html");
  const std::string page((std::istreambuf_iterator<char>(page_in)), std::istreambuf_iterator<char>());
  for (const char* needle : {"rcurves.png", ">A<", ">B<", ">broken<", "id=\"statistics\"",
                             "id=\"joint\"", "J<sub>B</sub>"})
    EXPECT_NE(page.find(needle), std::string::npos) << needle;
  EXPECT_TRUE(fs::exists(report / "campaign_data_0.dat"));
  EXPECT_TRUE(fs::exists(report / "campaign_fit_1.dat"));
  // The page in headless Chromium: every figure decodes, no script error.
  const std::string chromium = report_check::FindChromium();
  if (chromium.empty()) {
    std::cout << "chromium not installed: browser check of the campaign report skipped\n";
  } else {
    const std::string dom = report_check::DumpDom(chromium, report / "index.html", dir.path);
    EXPECT_EQ(report_check::CheckStatus(dom), "ok") << dom.substr(0, 400);
  }
}

}  // namespace
}  // namespace bridgefit::campaign

namespace bridgefit::campaign {
namespace {

// The CLI's own job: a manifest fault exits 1 before any fit, with the
// manifest line, and writes nothing.
// --joint-parameters: a name outside sigma_c, J_B, J_tip_c is a usage
// error (exit 2) naming the flag and the allowed names, before any fit.
TEST(CampaignCli, UnknownJointParameterExitsTwoNamingTheFlag) {
  WorkDir dir;
  const fs::path m = dir.Write("c.toml", kHead);
  const auto r = testing::RunCli("campaign " + m.string() + " --out " +
                                 (dir.path / "out").string() + " --joint --joint-parameters sigma_c,K");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--joint-parameters"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sigma_c, J_B, J_tip_c"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path / "out"));
}

TEST(CampaignCli, ManifestFaultExitsOneNamingTheLineAndWritesNothing) {
  WorkDir dir;
  const fs::path m = dir.Write(
      "c.toml", std::string(kHead) + "[[specimen]]\nname = \"B\"\nrecord = \"gone.csv\"\n");
  const auto r = testing::RunCli("campaign " + m.string() + " --out " + (dir.path / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("c.toml:11"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("gone.csv"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path / "out"));
}

}  // namespace
}  // namespace bridgefit::campaign
