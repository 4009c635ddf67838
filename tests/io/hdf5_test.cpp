#include "bridgefit/io/hdf5.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "bridgefit/core/error.hpp"

namespace bridgefit::io {
namespace {

std::filesystem::path TempDir() {
  const auto dir = std::filesystem::temp_directory_path() / "bf_hdf5_test";
  std::filesystem::create_directories(dir);
  return dir;
}

ExperimentRecord SampleRecord() {
  ExperimentRecord r;
  r.source = "sample.csv";
  r.time = {0, 1, 2};
  r.load = {0, 10.5, 20.25};
  r.displacement = {0, 1e-4, 2e-4};
  r.crack_length = {0.03, 0.03, 0.031};
  r.images = {"img 000.png", "img 001.png", "img 002.png"};
  r.metadata["specimen"] = "CT W=100 mm";
  r.rows_read = 5;
  r.rows_dropped_nan = 1;
  r.rows_repeated = 1;
  return r;
}

RCurve SampleCurve() {
  RCurve c;
  c.method = "energy";
  c.r_kind = "energy";
  c.source = "sample.csv";
  c.crack_length = {0.03, 0.035, 0.04};
  c.R = {2210, 2400, 2550};
  c.R_uncertainty = {20, 25, 30};
  c.initial_crack_length = 0.03;
  c.initiation_R = 2210;
  return c;
}

SimulationResult SampleSimulation() {
  SimulationResult s;
  s.model = "reduced";
  s.status = RunStatus::kNotConverged;
  s.message = "stopped at max_crack_length";
  s.steady_state_reached = true;
  s.steady_state_crack_length = 0.071;
  s.initiation_load = 512.0;
  s.wall_s = 0.012;
  s.figures["resolution"] = 4;
  for (int i = 0; i < 4; ++i) {
    SimulationPoint p;
    p.crack_length = 0.03 + 0.001 * i;
    p.R = 2210 + i;
    p.R_energy = 2211 + i;
    p.J_tip = 2210;
    p.J_ff = 2300 + i;
    p.delta_root = 1e-4 * i;
    p.root_position = 0.03;
    p.bridging_zone_length = 0.001 * i;
    p.load = 500 - i;
    p.displacement = 1e-3 * i;
    p.cmod = 1.5e-3 * i;
    s.points.push_back(p);
  }
  return s;
}

TEST(Hdf5, RoundTripOfEveryRecordType) {
  const auto path = TempDir() / "roundtrip.h5";
  {
    H5Writer writer(path);
    WriteRecordH5(writer, SampleRecord());
    WriteRecordH5(writer, SampleCurve());
    WriteRecordH5(writer, SampleSimulation());
    writer.Commit();
  }
  H5Reader reader(path);
  const ExperimentRecord r = ReadExperimentH5(reader);
  const ExperimentRecord r0 = SampleRecord();
  EXPECT_EQ(r.load, r0.load);
  EXPECT_EQ(r.displacement, r0.displacement);
  EXPECT_EQ(r.time, r0.time);
  EXPECT_EQ(r.crack_length, r0.crack_length);
  EXPECT_EQ(r.images, r0.images);
  EXPECT_EQ(r.source, r0.source);
  EXPECT_EQ(r.rows_dropped_nan, 1);
  std::string units;
  reader.ReadVector("/experiment/displacement", &units);
  EXPECT_EQ(units, "m");

  const RCurve c = ReadRCurveH5(reader);
  const RCurve c0 = SampleCurve();
  EXPECT_EQ(c.R, c0.R);
  EXPECT_EQ(c.R_uncertainty, c0.R_uncertainty);
  EXPECT_EQ(c.crack_length, c0.crack_length);
  EXPECT_EQ(c.method, "energy");
  EXPECT_DOUBLE_EQ(c.initiation_R, 2210);

  const SimulationResult s = ReadSimulationH5(reader);
  const SimulationResult s0 = SampleSimulation();
  ASSERT_EQ(s.points.size(), s0.points.size());
  EXPECT_EQ(s.status, RunStatus::kNotConverged);
  EXPECT_EQ(s.message, s0.message);
  EXPECT_TRUE(s.steady_state_reached);
  EXPECT_DOUBLE_EQ(s.steady_state_crack_length, 0.071);
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_DOUBLE_EQ(s.points[i].R_energy, s0.points[i].R_energy);
    EXPECT_DOUBLE_EQ(s.points[i].cmod, s0.points[i].cmod);
  }
}

TEST(Hdf5, AttributesOnNewNestedGroups) {
  const auto path = TempDir() / "nested.h5";
  {
    H5Writer writer(path);
    writer.WriteAttribute("/fit/parameters/sigma_c", "units", "Pa");
    writer.WriteAttribute("/fit/parameters/sigma_c", "value", 0.45e6);
    writer.Commit();
  }
  H5Reader reader(path);
  EXPECT_EQ(reader.ReadStringAttribute("/fit/parameters/sigma_c", "units"), "Pa");
  EXPECT_DOUBLE_EQ(reader.ReadNumberAttribute("/fit/parameters/sigma_c", "value"), 0.45e6);
}

TEST(Hdf5, UncommittedWriterLeavesNoFile) {
  const auto dir = TempDir() / "uncommitted";
  std::filesystem::create_directories(dir);
  {
    H5Writer writer(dir / "half.h5");
    writer.WriteVector("/x", {1, 2, 3}, "m");
  }  // a failure before Commit()
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(Hdf5, ReaderErrors) {
  const auto dir = TempDir();
  EXPECT_THROW(H5Reader(dir / "nope.h5"), Error);
  const auto text = dir / "text.h5";
  std::FILE* f = std::fopen(text.c_str(), "w");
  std::fputs("not hdf5", f);
  std::fclose(f);
  try {
    H5Reader reader(text);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not an HDF5 file"), std::string::npos);
  }
}

// The layout is readable by h5py (or h5dump when h5py is missing).
TEST(Hdf5, ReadableByH5pyOrH5dump) {
  const auto path = TempDir() / "external.h5";
  {
    H5Writer writer(path);
    WriteRecordH5(writer, SampleCurve());
    writer.Commit();
  }
  const bool have_h5py = std::system("/usr/bin/python3 -c 'import h5py' 2>/dev/null") == 0;
  if (have_h5py) {
    const std::string script =
        "import h5py,sys; f=h5py.File(sys.argv[1],'r'); R=f['/rcurve/R']; "
        "u=R.attrs['units']; u=u.decode() if isinstance(u,bytes) else u; "
        "assert u=='J/m^2', u; assert list(R[:])==[2210,2400,2550]; "
        "m=f['/rcurve'].attrs['method']; m=m.decode() if isinstance(m,bytes) else m; "
        "assert m=='energy', m";
    EXPECT_EQ(std::system(("/usr/bin/python3 -c \"" + script + "\" " + path.string()).c_str()), 0);
  } else if (std::system("h5dump --version > /dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("h5dump -a /rcurve/R/units " + path.string() +
                           " | grep -q 'J/m\\^2'").c_str()), 0);
  } else {
    GTEST_SKIP() << "neither h5py nor h5dump is installed";
  }
}

}  // namespace
}  // namespace bridgefit::io
