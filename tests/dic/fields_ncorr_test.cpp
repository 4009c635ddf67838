// Ncorr MAT files (v5 and v7.3): the layout written by the project reads back
// with the right grid, units and failed points; frames of one file are
// frames of the sequence; a known-tip field gives its tip within 0.5 mm;
// malformed files name the file and the variable.
//
// No public Ncorr output file could be found to keep here (the stored public
// sources hold Ncorr's MATLAB code and scripts that read data_dic_save, no
// .mat data): the layout follows Ncorr 1.2's ncorr.m and
// ncorr_gui_formatdisp.m (data_dic_save.displacements(k).plot_u_ref_formatted
// in dispinfo.units = pixels x dispinfo.pixtounits on a grid of spacing + 1 px).
#include <matio.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/speckle.hpp"

namespace bridgefit::dic {
namespace {
namespace fs = std::filesystem;

fs::path TempDir(const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("bf_ncorr_" + std::to_string(::getpid()) + "_" + tag);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// LEFM field in mm on a 1 mm grid, x 0..90, y 0..40, crack on y = 20.5 from
// x = 0 to the tip.
FieldFile GridField(double tip_x) {
  ModeICrackField m;
  m.tip_x = tip_x;
  m.tip_y = 20.5;
  m.k_over_2mu = 0.004;
  m.translation_x = 0.02;
  m.translation_y = -0.01;
  m.rotation = 2e-4;
  FieldFile f;
  f.unit = "mm";
  f.m_per_unit = 1e-3;
  DisplacementField& d = f.field;
  for (int iy = 0; iy <= 40; ++iy)
    for (int ix = 0; ix <= 90; ++ix) {
      double u, v;
      m(ix, iy, &u, &v);
      d.x.push_back(ix);
      d.y.push_back(iy);
      d.u.push_back(u);
      d.v.push_back(v);
      d.zncc.push_back(1);
      d.iterations.push_back(0);
      d.status.push_back(PointStatus::kOk);
    }
  d.nx = 91;
  d.ny = 41;
  return f;
}

class NcorrRoundTrip : public ::testing::TestWithParam<bool> {};

TEST_P(NcorrRoundTrip, GridUnitsFailedPointsAndTip) {
  const bool v73 = GetParam();
  const fs::path dir = TempDir(v73 ? "v73" : "v5");
  const std::vector<double> tips = {31.3, 44.8, 57.6};
  std::vector<FieldFile> frames;
  for (double t : tips) frames.push_back(GridField(t));
  frames[0].field.status[5 * 91 + 60] = PointStatus::kLowCorrelation;  // one failed node
  const fs::path file = dir / "ncorr_run.mat";
  WriteNcorrFile(file, frames, {.spacing_px = 4, .v73 = v73});
  EXPECT_TRUE(IsMatFile(file));

  const NcorrFile ncorr(file);
  EXPECT_EQ(ncorr.MatVersion(), v73 ? 73 : 5);
  EXPECT_EQ(ncorr.Frames(), 3u);
  EXPECT_EQ(ncorr.Spacing(), 4);
  const FieldFile back = ncorr.Frame(0);
  EXPECT_EQ(back.format, FieldFormat::kNcorr);
  EXPECT_EQ(back.unit, "mm");
  EXPECT_DOUBLE_EQ(back.m_per_unit, 1e-3);
  ASSERT_EQ(back.field.size(), 91u * 41u);
  EXPECT_EQ(back.failed, 1u);
  EXPECT_FALSE(back.field.ok(5 * 91 + 60));
  for (size_t i : {size_t{0}, size_t{17}, size_t{5 * 91 + 61}, size_t{40 * 91 + 90}}) {
    EXPECT_NEAR(back.field.x[i], frames[0].field.x[i], 1e-12);
    EXPECT_NEAR(back.field.y[i], frames[0].field.y[i], 1e-12);
    EXPECT_DOUBLE_EQ(back.field.u[i], frames[0].field.u[i]);
    EXPECT_DOUBLE_EQ(back.field.v[i], frames[0].field.v[i]);
  }
  EXPECT_NEAR(PointSpacing(back.field), 1.0, 1e-12);
  EXPECT_EQ(ncorr.FrameName(2), file.string() + ": displacements(3)");

  // The file through the sequence: three frames, each tip within 0.5 mm.
  CrackSequenceOptions o;
  o.show_progress = false;
  o.tip.threshold_floor_px = 0.001;
  o.path.min_jump_px = 0.001;
  o.has_line = false;
  const CrackSequenceResult r = AnalyzeCrackFields(ExpandFieldArguments({dir.string()}), o);
  ASSERT_EQ(r.frames.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    const FrameResult& f = r.frames[k];
    ASSERT_TRUE(f.has_length) << f.image;
    EXPECT_EQ(f.tip.method, TipMethod::kWilliams);
    // No line: the path runs from the field's edge at x = 0.
    EXPECT_NEAR(f.crack_length_raw_m * 1e3, tips[k], 0.5) << f.image;
    EXPECT_NE(f.image.find("displacements(" + std::to_string(k + 1) + ")"), std::string::npos);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Versions, NcorrRoundTrip, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "v73" : "v5"; });

TEST(Ncorr, PixelsAndOpaqueRoiUseZeroAsOutside) {
  const fs::path dir = TempDir("px");
  FieldFile f = GridField(40);
  f.unit = "px";
  f.m_per_unit = 0;
  for (double& x : f.field.x) x *= 3;  // grid step 3 px = spacing 2
  for (double& y : f.field.y) y *= 3;
  f.field.status[100] = PointStatus::kLowCorrelation;
  const fs::path file = dir / "px.mat";
  WriteNcorrFile(file, {f}, {.spacing_px = 2, .v73 = false, .roi_mask = false});
  const FieldFile back = NcorrFile(file).Frame(0);
  EXPECT_EQ(back.unit, "px");
  EXPECT_TRUE(back.IsPixels());
  EXPECT_DOUBLE_EQ(back.field.x[5], 15);
  EXPECT_DOUBLE_EQ(back.field.y[91], 3);
  // Without a mask the node the writer left at u = v = 0 is outside.
  EXPECT_EQ(back.failed, 1u);
  EXPECT_FALSE(back.field.ok(100));
  // A px field whose step is not spacing + 1 is refused.
  EXPECT_THROW(WriteNcorrFile(dir / "bad.mat", {f}, {.spacing_px = 4}), Error);
  EXPECT_FALSE(fs::exists(dir / "bad.mat"));
  fs::remove_all(dir);
}

// matio handles for building malformed files.
struct MatFile {
  explicit MatFile(const fs::path& p, bool v73)
      : mat(Mat_CreateVer(p.c_str(), nullptr, v73 ? MAT_FT_MAT73 : MAT_FT_MAT5)) {}
  ~MatFile() { Mat_Close(mat); }
  void Write(matvar_t* v) {
    Mat_VarWrite(mat, v, MAT_COMPRESSION_NONE);
    Mat_VarFree(v);
  }
  mat_t* mat;
};

matvar_t* Scalar(const char* name, double value) {
  size_t dims[2] = {1, 1};
  return Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, &value, 0);
}

matvar_t* Text(const char* name, const std::string& text) {
  size_t dims[2] = {1, text.size()};
  return Mat_VarCreate(name, MAT_C_CHAR, MAT_T_UTF8, 2, dims, const_cast<char*>(text.data()), 0);
}

// data_dic_save with dispinfo (units, pixtounits) and one frame whose u plot
// is `u_plot` (nullptr: missing).
void WriteMalformed(const fs::path& p, bool v73, const std::string& units, double pixtounits,
                    bool with_u, bool with_dispinfo) {
  MatFile m(p, v73);
  std::vector<double> plot(12, 0.1);
  size_t pd[2] = {3, 4};
  const char* dfields[] = {"plot_u_ref_formatted", "plot_v_ref_formatted"};
  size_t one[2] = {1, 1};
  matvar_t* disp = Mat_VarCreateStruct("displacements", 2, one, dfields, 2);
  if (with_u)
    Mat_VarSetStructFieldByName(disp, "plot_u_ref_formatted", 0,
                                Mat_VarCreate("plot_u_ref_formatted", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, pd, plot.data(), 0));
  Mat_VarSetStructFieldByName(disp, "plot_v_ref_formatted", 0,
                              Mat_VarCreate("plot_v_ref_formatted", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, pd, plot.data(), 0));
  const char* ifields[] = {"spacing", "pixtounits", "units"};
  matvar_t* info = Mat_VarCreateStruct("dispinfo", 2, one, ifields, 3);
  Mat_VarSetStructFieldByName(info, "spacing", 0, Scalar("spacing", 3));
  Mat_VarSetStructFieldByName(info, "pixtounits", 0, Scalar("pixtounits", pixtounits));
  Mat_VarSetStructFieldByName(info, "units", 0, Text("units", units));
  const char* rfields[] = {"displacements", "dispinfo"};
  matvar_t* root = Mat_VarCreateStruct("data_dic_save", 2, one, rfields, with_dispinfo ? 2 : 1);
  Mat_VarSetStructFieldByName(root, "displacements", 0, disp);
  if (with_dispinfo) Mat_VarSetStructFieldByName(root, "dispinfo", 0, info);
  else Mat_VarFree(info);
  m.Write(root);
}

void ExpectNcorrError(const fs::path& p, const std::string& variable) {
  try {
    NcorrFile f(p);
    f.Frame(0);
    FAIL() << "no error for " << p;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(p.string()), std::string::npos) << what;
    EXPECT_NE(what.find(variable), std::string::npos) << what;
  }
}

TEST(Ncorr, BadFilesNameFileAndVariable) {
  const fs::path dir = TempDir("bad");
  for (bool v73 : {false, true}) {
    SCOPED_TRACE(v73 ? "v7.3" : "v5");
    const std::string tag = v73 ? "73" : "5";
    WriteMalformed(dir / ("ok" + tag + ".mat"), v73, "mm", 0.05, true, true);
    EXPECT_EQ(NcorrFile(dir / ("ok" + tag + ".mat")).Frame(0).field.size(), 12u);
    WriteMalformed(dir / ("no_u" + tag + ".mat"), v73, "mm", 0.05, false, true);
    ExpectNcorrError(dir / ("no_u" + tag + ".mat"), "data_dic_save.displacements(1).plot_u_ref_formatted");
    WriteMalformed(dir / ("unit" + tag + ".mat"), v73, "furlongs", 0.05, true, true);
    ExpectNcorrError(dir / ("unit" + tag + ".mat"), "data_dic_save.dispinfo.units");
    WriteMalformed(dir / ("scale" + tag + ".mat"), v73, "mm", -1, true, true);
    ExpectNcorrError(dir / ("scale" + tag + ".mat"), "data_dic_save.dispinfo.pixtounits");
    WriteMalformed(dir / ("px" + tag + ".mat"), v73, "pixels", 0.05, true, true);
    ExpectNcorrError(dir / ("px" + tag + ".mat"), "data_dic_save.dispinfo.pixtounits");
    WriteMalformed(dir / ("noinfo" + tag + ".mat"), v73, "mm", 0.05, true, false);
    ExpectNcorrError(dir / ("noinfo" + tag + ".mat"), "data_dic_save.dispinfo");
    {
      MatFile m(dir / ("other" + tag + ".mat"), v73);
      m.Write(Scalar("something_else", 1));
    }
    ExpectNcorrError(dir / ("other" + tag + ".mat"), "data_dic_save");
  }
  // Not a MAT file at all; a truncated one; an empty one.
  std::ofstream(dir / "text.mat") << "x [mm], y [mm], u [mm], v [mm]\n1, 2, 3, 4\n";
  ExpectNcorrError(dir / "text.mat", "");
  {
    std::ifstream in(dir / "ok5.mat", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "cut5.mat", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::ifstream in73(dir / "ok73.mat", std::ios::binary);
    std::string bytes73((std::istreambuf_iterator<char>(in73)), {});
    std::ofstream(dir / "cut73.mat", std::ios::binary) << bytes73.substr(0, bytes73.size() / 2);
  }
  ExpectNcorrError(dir / "cut5.mat", "");
  ExpectNcorrError(dir / "cut73.mat", "");
  std::ofstream(dir / "empty.mat");
  ExpectNcorrError(dir / "empty.mat", "");
  // A .mat that is no MAT file is not read as text.
  {
    FieldFrames frames({dir / "text.mat"});
    FieldFile f;
    std::string name;
    try {
      frames.Next(&f, &name);
      ADD_FAILURE() << "text.mat read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("not a MATLAB MAT file"), std::string::npos) << e.what();
    }
  }
  // A MAT file handed to the text reader points to the MAT reader.
  EXPECT_THROW(ReadFieldFile(dir / "ok5.mat"), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit::dic
