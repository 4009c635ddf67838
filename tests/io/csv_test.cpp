#include "bridgefit/io/csv.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bridgefit/core/error.hpp"

namespace bridgefit::io {
namespace {

class CsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("bf_csv_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  std::string ErrorOf(const std::filesystem::path& path, const RecordColumns& columns = {}) {
    try {
      ReadRecordCsv(path, columns);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for " << path;
    return "";
  }
  std::filesystem::path dir_;
};

void ExpectContains(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
}

TEST_F(CsvTest, RecordWithUnitsInHeader) {
  const auto path = Write("rec.csv",
                          "time [s], load [kN], displacement [mm], crack_length [mm]\n"
                          "0, 0, 0, 30\n1, 0.5, 0.25, 30\n2, 0.9, 0.5, 31.5\n");
  const ExperimentRecord r = ReadRecordCsv(path, {});
  ASSERT_EQ(r.size(), 3u);
  EXPECT_DOUBLE_EQ(r.load[2], 900.0);
  EXPECT_DOUBLE_EQ(r.displacement[1], 0.25e-3);
  EXPECT_DOUBLE_EQ(r.crack_length[2], 31.5e-3);
  EXPECT_DOUBLE_EQ(r.time[2], 2.0);
  EXPECT_EQ(r.rows_dropped_nan, 0);
}

TEST_F(CsvTest, NanAndRepeatedRowsAreCountedNotSilentlyDropped) {
  const auto path = Write("rec.csv",
                          "time [s], load [N], displacement [mm]\n"
                          "0, 0, 0\n1, 5, 0.1\n1, 5, 0.1\n2, NaN, 0.2\n3, , 0.3\n4, 9, 0.4\n");
  const ExperimentRecord r = ReadRecordCsv(path, {});
  EXPECT_EQ(r.rows_read, 6);
  EXPECT_EQ(r.rows_dropped_nan, 2);
  EXPECT_EQ(r.rows_repeated, 1);
  EXPECT_EQ(r.size(), 3u);
  EXPECT_FALSE(r.has_crack_length());
}

TEST_F(CsvTest, ColumnMappingForTheDcbFiles) {
  // Header style of ../shared/data/dcb-composite: Time,Disp,Force,CrackExt,G_I.
  const auto path = Write("dcb.csv",
                          "Time,Disp,Force,CrackExt,G_I\n16,0,0,37.64,0\n"
                          "17,0.0820135,2.91708128074084,37.64,0.000325\n"
                          "18,0.169834,4.88800022131104,37.64,NaN\n");
  RecordColumns columns;
  ApplyColumnMapping("time=Time,displacement=Disp,load=Force,crack_length=CrackExt", columns);
  ApplyUnitMapping("time=s,displacement=mm,load=N,crack_length=mm", columns);
  const ExperimentRecord r = ReadRecordCsv(path, columns);
  ASSERT_EQ(r.size(), 3u);  // G_I is not a used column: its NaN does not drop the row
  EXPECT_DOUBLE_EQ(r.displacement[2], 0.169834e-3);
  EXPECT_DOUBLE_EQ(r.crack_length[0], 37.64e-3);
}

TEST_F(CsvTest, BadRecords) {
  RecordColumns columns;
  ExpectContains(ErrorOf(Write("a.csv", "time [s], load [N]\n0, 1\n")),
                 {"a.csv", "'displacement'", "missing column", "columns found: 'time', 'load'"});
  ExpectContains(ErrorOf(Write("b.csv", "time [s], load, displacement [mm]\n0, 1, 2\n")),
                 {"b.csv", "'load'", "no unit", "load [N]"});
  ExpectContains(ErrorOf(Write("c.csv", "time [s], load [mm], displacement [mm]\n0, 1, 2\n")),
                 {"c.csv", "'load'", "wrong unit", "force"});
  ExpectContains(ErrorOf(Write("d.csv", "time [s], load [N], displacement [mm]\n0, 1\n")),
                 {"d.csv:2", "row has 2 cells but the header has 3"});
  ExpectContains(ErrorOf(Write("e.csv", "time [s], load [N], displacement [mm]\n0, 1, 2\n1, abc, 3\n")),
                 {"e.csv:3", "'load'", "not a number", "abc"});
  ExpectContains(ErrorOf(Write("f.csv", "")), {"f.csv", "empty"});
  std::string binary;
  for (int i = 0; i < 300; ++i) binary += static_cast<char>(i % 256);
  ExpectContains(ErrorOf(Write("g.csv", binary)), {"g.csv", "binary"});
  ExpectContains(ErrorOf(Write("h.csv", "1, 2, 3\n4, 5, 6\n")), {"h.csv:1", "not a header"});
  ExpectContains(ErrorOf(Write("i.csv", "time [s], load [N], displacement [mm]\n")),
                 {"i.csv", "no data rows"});
  ExpectContains(ErrorOf(dir_ / "nope.csv"), {"nope.csv", "cannot open"});
  EXPECT_THROW(ApplyColumnMapping("force", columns), Error);
  EXPECT_THROW(ApplyUnitMapping("weight=kg", columns), Error);
}

}  // namespace
}  // namespace bridgefit::io
