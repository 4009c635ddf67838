// Writers of displacement-field exports, one per format read by
// fields_read.cpp (so tests can write known-tip fields and read them back).
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"

namespace bridgefit::dic {
namespace {

std::string Unit(const FieldFile& f) { return f.unit.empty() ? std::string("px") : f.unit; }

std::string WriteCsv(const FieldFile& f) {
  const std::string u = Unit(f);
  std::string out = fmt::format("x [{0}], y [{0}], u [{0}], v [{0}], valid\n", u);
  const DisplacementField& d = f.field;
  for (size_t i = 0; i < d.size(); ++i)
    out += fmt::format("{:.9g}, {:.9g}, {:.9g}, {:.9g}, {}\n", d.x[i], d.y[i], d.u[i], d.v[i],
                       d.ok(i) ? 1 : 0);
  return out;
}

// Failed points are left out (Aramis exports only the facets it computed).
std::string WriteAramis(const FieldFile& f) {
  const std::string u = Unit(f);
  std::string out =
      "# Process data:\n# written by bridgefit (nodemap layout of GOM Aramis/Correlate exports)\n"
      "####################################################################################################\n";
  out += fmt::format("#        ID;  x_undef [{0}];  y_undef [{0}];  z_undef [{0}];  u [{0}];  v [{0}];  w [{0}]\n", u);
  const DisplacementField& d = f.field;
  size_t id = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (!d.ok(i)) continue;
    out += fmt::format("{:10d}; {:.10g}; {:.10g}; 0; {:.12g}; {:.12g}; 0\n", ++id, d.x[i], d.y[i], d.u[i], d.v[i]);
  }
  return out;
}

std::string WriteDice(const FieldFile& f) {
  if (!f.IsPixels())
    throw Error(ErrorKind::kUsage, "DICe solutions are in pixels",
                {.field = "unit", .value = f.unit, .expected = "a field in px"});
  std::string out =
      "***\n*** Digital Image Correlation Engine (DICe) solution layout, written by bridgefit\n***\n"
      "*** Coordinates given with (0,0) as upper left corner of image, x positive right, y positive down\n***\n"
      "SUBSET_ID,COORDINATE_X,COORDINATE_Y,DISPLACEMENT_X,DISPLACEMENT_Y,SIGMA,GAMMA,MATCH\n";
  const DisplacementField& d = f.field;
  for (size_t i = 0; i < d.size(); ++i) {
    const bool ok = d.ok(i);
    out += fmt::format("{},{:.6E},{:.6E},{:.9E},{:.9E},{:.4E},{:.4E},{:.4E}\n", i, d.x[i], d.y[i],
                       ok ? d.u[i] : 0.0, ok ? d.v[i] : 0.0, ok ? 0.01 : -1.0, ok ? 0.0 : -1.0,
                       ok ? 0.0 : -1.0);
  }
  return out;
}

// DaVis marks nothing as failed in its text export: failed points are
// written as NaN, which the reader takes as failed.
std::string WriteDavis(const FieldFile& f) {
  const std::string u = f.IsPixels() ? "pixel" : Unit(f);
  const DisplacementField& d = f.field;
  std::string out = fmt::format("#DaVis 8.4.0 2D-vector 1 {} {} \"\" \"{}\" \"\" \"{}\" \"displacement\" \"{}\"\n",
                                d.ny, d.nx, u, u, u);
  for (size_t i = 0; i < d.size(); ++i) {
    if (d.ok(i))
      out += fmt::format("{:.9g}\t{:.9g}\t{:.9g}\t{:.9g}\n", d.x[i], d.y[i], d.u[i], d.v[i]);
    else
      out += fmt::format("{:.9g}\t{:.9g}\tnan\tnan\n", d.x[i], d.y[i]);
  }
  return out;
}

}  // namespace

std::string WriteFieldText(const FieldFile& field, FieldFormat format) {
  switch (format) {
    case FieldFormat::kCsv: return WriteCsv(field);
    case FieldFormat::kAramis: return WriteAramis(field);
    case FieldFormat::kDice: return WriteDice(field);
    case FieldFormat::kDavis: return WriteDavis(field);
    case FieldFormat::kNcorr:
      throw Error(ErrorKind::kUsage, "Ncorr output is a binary MAT file, not text",
                  {.field = "format", .value = "ncorr", .expected = "WriteNcorrFile"});
  }
  throw Error(ErrorKind::kInternal, "unknown field format");
}

void WriteFieldFile(const std::filesystem::path& path, const FieldFile& field, FieldFormat format) {
  WriteTextFileAtomic(path, WriteFieldText(field, format));
}

}  // namespace bridgefit::dic
