#pragma once
// Displacement fields exported by other DIC software (one frame per file),
// read by their header names - never by column position - with units:
//
//  kCsv:    plain CSV, header "x [mm], y [mm], u [mm], v [mm]" (any length
//           unit or px, same unit for all four; optional "valid" 0/1 column).
//  kAramis: GOM Aramis/Correlate nodemap text: '#' comment lines, the last of
//           which names the ';'-separated columns ("x_undef [mm]; y_undef [mm];
//           ...; u [mm]; v [mm]; ...").
//  kDice:   DICe solution text: '***' header lines, then a comma-separated
//           table with SUBSET_ID, COORDINATE_X, COORDINATE_Y, DISPLACEMENT_X,
//           DISPLACEMENT_Y and SIGMA (-1 = failed subset); pixels.
//  kDavis:  LaVision DaVis vector text: first line
//           '#DaVis <version> 2D-vector <step> <ny> <nx> "" "<unit x>" "" "<unit y>"
//           "displacement" "<unit>"', then x, y, u, v rows.
//
// A point is failed when the file marks it (SIGMA = -1, valid = 0) or any of
// x, y, u, v is not a finite number. Each format has one reader and one
// writer here (the writers let tests write known-tip fields). Every reader
// takes the text (or a path) and throws Error(kInput) naming the file, the
// line and the column for anything it cannot read; files over
// kMaxFieldFileBytes are refused.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

namespace bridgefit::dic {

enum class FieldFormat { kCsv, kAramis, kDice, kDavis };
const char* FieldFormatName(FieldFormat format);
// "csv" | "aramis" | "dice" | "davis"; throws Error(kUsage) otherwise.
FieldFormat ParseFieldFormat(const std::string& text);

inline constexpr std::size_t kMaxFieldFileBytes = std::size_t{1} << 30;  // 1 GiB

// One frame. Positions and displacements are in `unit`; the field is a
// scattered point list (nx = size, ny = 1) unless the file is a grid.
struct FieldFile {
  DisplacementField field;
  std::string unit;         // "px" or a length unit as written ("mm", "m", "um", ...)
  double m_per_unit = 0;    // metres per unit; 0 for px (a scale must be given)
  FieldFormat format = FieldFormat::kCsv;
  std::size_t failed = 0;   // points the file marks failed (or non-finite)
  bool IsPixels() const { return m_per_unit == 0; }
};

// The format from the first line(s): '#DaVis' -> DaVis, '***' -> DICe,
// '#' lines with ';' columns -> Aramis, otherwise CSV.
FieldFormat DetectFieldFormat(const std::string& text);

// `name` is used in error messages (the file name).
FieldFile ReadFieldText(const std::string& text, const std::string& name);
FieldFile ReadFieldFile(const std::filesystem::path& path);

// `unit` of the field: "px" or a length unit. DICe is pixel-only (Error(kUsage)
// for a field in length units).
std::string WriteFieldText(const FieldFile& field, FieldFormat format);
void WriteFieldFile(const std::filesystem::path& path, const FieldFile& field, FieldFormat format);

// Field files from arguments: a folder (its .txt/.csv/.dat files), a glob or
// files; folders and globs in natural order ("f2" before "f10").
std::vector<std::filesystem::path> ExpandFieldArguments(const std::vector<std::string>& args);

// Median distance between neighbouring points (the node or grid spacing),
// in the field's unit; 0 for fewer than two valid points.
double PointSpacing(const DisplacementField& field);

}  // namespace bridgefit::dic
