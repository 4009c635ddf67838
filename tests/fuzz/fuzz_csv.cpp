// libFuzzer harness: CSV test records (io/csv.cpp), parsed and converted the
// way `bridgefit rcurve record.csv` does, plus every column in SI.
#include <cstddef>
#include <cstdint>
#include <string>

#include "bridgefit/io/csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace bridgefit;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  InputLimits limits;  // small limits: the fuzzer reaches them quickly
  limits.max_csv_rows = 2000;
  limits.max_csv_columns = 64;
  limits.max_line_bytes = 4096;
  try {
    const io::CsvTable table = io::ParseCsvTable(text, "fuzz.csv", limits);
    for (const std::string& name : table.names) {
      try {
        (void)table.ColumnSi(name, Dimension::Length());
      } catch (const Error&) {
      }
    }
    (void)io::RecordFromCsvTable(table, io::RecordColumns{});
  } catch (const Error&) {
  }
  return 0;
}
