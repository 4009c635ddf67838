#pragma once
// CSV import with units in the header: `time [s], load [N], displacement [mm]`.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/core/records.hpp"
#include "bridgefit/core/units.hpp"

namespace bridgefit::io {

// A numeric table: columns by header name, with the unit given in brackets
// (empty when none). Empty cells and "NaN" read as NaN.
struct CsvTable {
  std::string source;
  std::vector<std::string> names;              // header names, trimmed, without units
  std::vector<std::string> units;              // unit text in brackets, "" if none
  std::vector<std::vector<double>> columns;    // columns[i][row]
  std::vector<int> lines;                      // file line of each row (1-based)
  std::vector<std::vector<std::string>> text;  // the raw cells, text[i][row]
  std::vector<int> bad_line;                   // first line with a non-numeric cell, 0 if none
  std::vector<std::string> bad_value;          // that cell

  std::size_t rows() const { return lines.size(); }
  // Index of a column by name (case-insensitive), or -1.
  int Find(const std::string& name) const;
  // Column converted to SI. `unit_override` replaces the header's unit; a
  // column with no unit anywhere is an error naming the expected unit.
  std::vector<double> ColumnSi(const std::string& name, const Dimension& dimension,
                               const std::string& unit_override = "") const;
  // Raw text of a column (e.g. image file names).
  const std::vector<std::string>& TextColumn(const std::string& name) const;
};

// Which size limit applies (core/input_limits.hpp): a test record, or a
// bridging-law table (much smaller).
enum class CsvKind { kRecord, kLawTable };

// Reads a CSV with a header row. Throws Error for an empty file, a binary
// file, a row with the wrong number of cells or a non-numeric cell, and for
// a file, line, row count or column count over its limit (the message names
// the limit and the environment variable that raises it).
CsvTable ReadCsvTable(const std::filesystem::path& path, CsvKind kind = CsvKind::kRecord);
// The same from text in memory (`source` names it in errors).
CsvTable ParseCsvTable(std::string_view content, const std::string& source,
                       const InputLimits& limits);

// How to read a test record: which header names hold which quantity and in
// which unit (overriding the header's brackets).
struct RecordColumns {
  std::string time = "time";
  std::string load = "load";
  std::string displacement = "displacement";
  std::string crack_length = "crack_length";  // optional column
  std::string image = "image";                // optional (text) column
  std::map<std::string, std::string> units;   // quantity -> unit, e.g. load -> N
};

// Parses "time=Time,displacement=Disp,load=Force" into `columns`, and
// "displacement=mm,load=N" into `columns.units`. Throws Error(kUsage).
void ApplyColumnMapping(const std::string& mapping, RecordColumns& columns);
void ApplyUnitMapping(const std::string& mapping, RecordColumns& columns);

// Reads a load-displacement record from CSV. Rows with NaN in a used column
// are dropped and counted; exact repeats of the previous row are dropped and
// counted. Throws Error for missing columns or units.
ExperimentRecord ReadRecordCsv(const std::filesystem::path& path, const RecordColumns& columns);
// The same from a table already read.
ExperimentRecord RecordFromCsvTable(const CsvTable& table, const RecordColumns& columns);

}  // namespace bridgefit::io
