#include "bridgefit/io/csv.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::io {
namespace {

std::string Trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  std::string out = s.substr(b, e - b);
  if (out.size() >= 2 && out.front() == '"' && out.back() == '"') out = out.substr(1, out.size() - 2);
  return out;
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

// "displacement [mm]" -> ("displacement", "mm"); "Force" -> ("Force", "").
std::pair<std::string, std::string> SplitNameUnit(const std::string& header) {
  const size_t open = header.find('[');
  const size_t close = header.rfind(']');
  if (open == std::string::npos || close == std::string::npos || close < open)
    return {Trim(header), ""};
  return {Trim(header.substr(0, open)), Trim(header.substr(open + 1, close - open - 1))};
}

bool ParseCell(const std::string& cell, double* value) {
  if (cell.empty()) {
    *value = NAN;
    return true;
  }
  const std::string lower = Lower(cell);
  if (lower == "nan" || lower == "na" || lower == "n/a") {
    *value = NAN;
    return true;
  }
  char* end = nullptr;
  *value = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() + cell.size();
}

bool LooksBinary(const std::string& text) {
  const size_t probe = std::min<size_t>(text.size(), 4096);
  size_t odd = 0;
  for (size_t i = 0; i < probe; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == 0) return true;
    if (c < 32 && c != '\n' && c != '\r' && c != '\t') ++odd;
  }
  return probe > 0 && odd * 20 > probe;
}

}  // namespace

int CsvTable::Find(const std::string& name) const {
  const std::string wanted = Lower(Trim(name));
  for (size_t i = 0; i < names.size(); ++i)
    if (Lower(names[i]) == wanted) return static_cast<int>(i);
  return -1;
}

std::vector<double> CsvTable::ColumnSi(const std::string& name, const Dimension& dimension,
                                       const std::string& unit_override) const {
  const int index = Find(name);
  if (index < 0) {
    std::string available;
    for (const auto& n : names) available += (available.empty() ? "'" : ", '") + n + "'";
    throw Error(ErrorKind::kInput, "missing column",
                {.file = source, .field = name, .expected = "a column named '" + name +
                                                            "' (columns found: " + available + ")"});
  }
  const std::string unit = unit_override.empty() ? units[index] : unit_override;
  const std::string& column_name = names[index];
  if (unit.empty() && !(dimension == Dimension::None()))
    throw Error(ErrorKind::kInput, "column has no unit",
                {.file = source, .field = column_name,
                 .expected = "a unit in the header, e.g. '" + column_name + " [" +
                             SiUnitName(dimension) + "]', or on the command line (--units)"});
  double scale = 1.0;
  if (!unit.empty()) {
    try {
      scale = ToSi(1.0, unit, dimension);
    } catch (const Error& e) {
      throw e.WithContext({.file = source, .field = column_name});
    }
  }
  if (bad_line[index] > 0)
    throw Error(ErrorKind::kInput, "not a number",
                {.file = source, .line = bad_line[index], .field = column_name,
                 .value = bad_value[index], .expected = "a number (or empty / NaN)"});
  std::vector<double> out(columns[index]);
  for (double& v : out) v *= scale;
  return out;
}

const std::vector<std::string>& CsvTable::TextColumn(const std::string& name) const {
  const int index = Find(name);
  if (index < 0)
    throw Error(ErrorKind::kInput, "missing column", {.file = source, .field = name});
  return text[index];
}

CsvTable ReadCsvTable(const std::filesystem::path& path, CsvKind kind) {
  const InputLimits limits = InputLimits::FromEnvironment();
  const bool law_table = kind == CsvKind::kLawTable;
  const std::string content = ReadFileLimited(
      path, law_table ? limits.max_table_bytes : limits.max_text_bytes,
      law_table ? InputLimits::kTableBytesVariable : InputLimits::kTextBytesVariable,
      law_table ? "bridging-law table file" : "CSV file");
  return ParseCsvTable(content, path.string(), limits);
}

CsvTable ParseCsvTable(std::string_view content_view, const std::string& source,
                       const InputLimits& limits) {
  const std::string content(content_view);
  if (content.find_first_not_of(" \t\r\n") == std::string::npos)
    throw Error(ErrorKind::kInput, "the file is empty",
                {.file = source, .expected = "a header row and data rows"});
  if (LooksBinary(content))
    throw Error(ErrorKind::kInput, "the file is not text (binary data)",
                {.file = source, .expected = "a comma-separated text file"});

  CsvTable table;
  table.source = source;
  std::istringstream lines(content);
  std::string line;
  int line_number = 0;
  bool have_header = false;
  while (std::getline(lines, line)) {
    if (++line_number == std::numeric_limits<int>::max())
      throw Error(ErrorKind::kInput, "more lines than a line number can count", {.file = source});
    if (line.size() > limits.max_line_bytes)
      CheckLimit(line.size(), limits.max_line_bytes, InputLimits::kLineBytesVariable,
                 "line " + std::to_string(line_number), "bytes", source);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
      line = line.substr(3);  // UTF-8 byte-order mark
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    const std::vector<std::string> cells = SplitCells(line);
    CheckLimit(cells.size(), limits.max_csv_columns, InputLimits::kCsvColumnsVariable,
               "line " + std::to_string(line_number), "columns", source);
    if (!have_header) {
      for (const std::string& cell : cells) {
        auto [name, unit] = SplitNameUnit(cell);
        if (name.empty())
          throw Error(ErrorKind::kInput, "empty column name in the header",
                      {.file = source, .line = line_number,
                       .expected = "a header such as 'time [s], load [N], displacement [mm]'"});
        double ignored;
        if (ParseCell(name, &ignored) && !name.empty())
          throw Error(ErrorKind::kInput, "the first row is numbers, not a header",
                      {.file = source, .line = line_number, .value = name,
                       .expected = "a header such as 'time [s], load [N], displacement [mm]'"});
        table.names.push_back(name);
        table.units.push_back(unit);
      }
      table.columns.resize(table.names.size());
      table.text.resize(table.names.size());
      table.bad_line.assign(table.names.size(), 0);
      table.bad_value.resize(table.names.size());
      have_header = true;
      continue;
    }
    if (cells.size() != table.names.size())
      throw Error(ErrorKind::kInput,
                  fmt::format("row has {} cells but the header has {} columns", cells.size(),
                              table.names.size()),
                  {.file = source, .line = line_number});
    for (size_t c = 0; c < cells.size(); ++c) {
      double value = NAN;
      if (!ParseCell(cells[c], &value)) {
        value = NAN;
        if (table.bad_line[c] == 0) {
          table.bad_line[c] = line_number;
          table.bad_value[c] = cells[c];
        }
      }
      table.columns[c].push_back(value);
      table.text[c].push_back(cells[c]);
    }
    table.lines.push_back(line_number);
    CheckLimit(table.lines.size(), limits.max_csv_rows, InputLimits::kCsvRowsVariable,
               "the CSV file", "data rows", source);
  }
  if (table.lines.empty())
    throw Error(ErrorKind::kInput, "no data rows after the header", {.file = source});
  return table;
}

void ApplyColumnMapping(const std::string& mapping, RecordColumns& columns) {
  std::stringstream stream(mapping);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw Error(ErrorKind::kUsage, "malformed column mapping",
                  {.field = "--columns", .value = item, .expected = "quantity=Header, e.g. load=Force"});
    const std::string key = Lower(Trim(item.substr(0, eq)));
    const std::string value = Trim(item.substr(eq + 1));
    if (key == "time") columns.time = value;
    else if (key == "load") columns.load = value;
    else if (key == "displacement") columns.displacement = value;
    else if (key == "crack_length") columns.crack_length = value;
    else if (key == "image") columns.image = value;
    else
      throw Error(ErrorKind::kUsage, "unknown quantity in column mapping",
                  {.field = "--columns", .value = key,
                   .expected = "time, load, displacement, crack_length or image"});
  }
}

void ApplyUnitMapping(const std::string& mapping, RecordColumns& columns) {
  std::stringstream stream(mapping);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw Error(ErrorKind::kUsage, "malformed unit mapping",
                  {.field = "--units", .value = item, .expected = "quantity=unit, e.g. displacement=mm"});
    const std::string key = Lower(Trim(item.substr(0, eq)));
    if (key != "time" && key != "load" && key != "displacement" && key != "crack_length")
      throw Error(ErrorKind::kUsage, "unknown quantity in unit mapping",
                  {.field = "--units", .value = key,
                   .expected = "time, load, displacement or crack_length"});
    columns.units[key] = Trim(item.substr(eq + 1));
  }
}

ExperimentRecord ReadRecordCsv(const std::filesystem::path& path, const RecordColumns& columns) {
  return RecordFromCsvTable(ReadCsvTable(path), columns);
}

ExperimentRecord RecordFromCsvTable(const CsvTable& table, const RecordColumns& columns) {
  auto unit_for = [&columns](const std::string& quantity) {
    const auto it = columns.units.find(quantity);
    return it == columns.units.end() ? std::string() : it->second;
  };
  ExperimentRecord record;
  record.source = table.source;
  const std::vector<double> load = table.ColumnSi(columns.load, Dimension::Force(), unit_for("load"));
  const std::vector<double> disp =
      table.ColumnSi(columns.displacement, Dimension::Length(), unit_for("displacement"));
  std::vector<double> time, crack;
  const bool has_time = table.Find(columns.time) >= 0;
  const bool has_crack = table.Find(columns.crack_length) >= 0;
  const bool has_image = table.Find(columns.image) >= 0;
  if (has_time) time = table.ColumnSi(columns.time, Dimension::Time(), unit_for("time"));
  if (has_crack)
    crack = table.ColumnSi(columns.crack_length, Dimension::Length(), unit_for("crack_length"));
  const std::vector<std::string>* images = has_image ? &table.TextColumn(columns.image) : nullptr;

  record.rows_read = static_cast<int>(table.rows());
  for (size_t r = 0; r < table.rows(); ++r) {
    // A missing crack length keeps the row (NaN): only the methods that need
    // the crack length drop it, and count it (experiment::CleanRecord).
    const bool finite = std::isfinite(load[r]) && std::isfinite(disp[r]) &&
                        (!has_time || std::isfinite(time[r])) &&
                        (!has_crack || std::isfinite(crack[r]) || std::isnan(crack[r]));
    if (!finite) {
      ++record.rows_dropped_nan;
      continue;
    }
    if (!record.load.empty() && load[r] == record.load.back() &&
        disp[r] == record.displacement.back() && (!has_time || time[r] == record.time.back()) &&
        (!has_crack || crack[r] == record.crack_length.back() ||
         (std::isnan(crack[r]) && std::isnan(record.crack_length.back())))) {
      ++record.rows_repeated;
      continue;
    }
    record.load.push_back(load[r]);
    record.displacement.push_back(disp[r]);
    if (has_time) record.time.push_back(time[r]);
    if (has_crack) record.crack_length.push_back(crack[r]);
    if (images) record.images.push_back((*images)[r]);
  }
  if (record.load.empty())
    throw Error(ErrorKind::kInput, "no complete rows (every row has a missing value)",
                {.file = record.source});
  record.metadata["columns"] = fmt::format("time={}, load={}, displacement={}, crack_length={}",
                                           has_time ? columns.time : "(none)", columns.load,
                                           columns.displacement,
                                           has_crack ? columns.crack_length : "(none)");
  record.Validate();
  return record;
}

}  // namespace bridgefit::io
