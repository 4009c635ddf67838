// Readers of displacement-field exports (CSV, Aramis nodemap, DICe, DaVis):
// columns found by their header names, units from the header, failed points
// kept with their status. See include/bridgefit/dic/fields.hpp.
#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/fields.hpp"
#include "bridgefit/dic/image.hpp"

namespace bridgefit::dic {

const char* FieldFormatName(FieldFormat format) {
  switch (format) {
    case FieldFormat::kCsv: return "csv";
    case FieldFormat::kAramis: return "aramis";
    case FieldFormat::kDice: return "dice";
    case FieldFormat::kDavis: return "davis";
    case FieldFormat::kNcorr: return "ncorr";
  }
  return "unknown";
}

FieldFormat ParseFieldFormat(const std::string& text) {
  for (FieldFormat f : {FieldFormat::kCsv, FieldFormat::kAramis, FieldFormat::kDice,
                        FieldFormat::kDavis, FieldFormat::kNcorr})
    if (text == FieldFormatName(f)) return f;
  throw Error(ErrorKind::kUsage, "unknown field format",
              {.field = "--format", .value = text, .expected = "csv, aramis, dice, davis or ncorr"});
}

namespace {
std::string Trim(std::string_view s);
std::string Lower(std::string s);
}  // namespace

std::string NormalizeFieldUnit(const std::string& unit, double* m_per_unit) {
  const std::string l = Lower(Trim(unit));
  if (l == "px" || l == "pixel" || l == "pixels" || l == "pix") {
    *m_per_unit = 0;
    return "px";
  }
  std::string u = Trim(unit);
  if (u == "\xC2\xB5m" || u == "\xCE\xBCm") u = "um";
  try {
    const Unit parsed = ParseUnit(u);
    if (parsed.dimension == Dimension::Length() && parsed.scale > 0) {
      *m_per_unit = parsed.scale;
      return u;
    }
  } catch (const Error&) {
  }
  throw Error(ErrorKind::kInput, "unit is not a length or px",
              {.value = unit, .expected = "px, pixels, mm, m, um, ..."});
}

namespace {

std::string Trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string_view> Lines(const std::string& text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

// Split on `sep`; sep == ' ' splits on any run of blanks and tabs.
std::vector<std::string> Split(std::string_view line, char sep) {
  std::vector<std::string> cells;
  if (sep == ' ') {
    std::string cur;
    for (char c : line) {
      if (c == ' ' || c == '\t') {
        if (!cur.empty()) cells.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    if (!cur.empty()) cells.push_back(cur);
    return cells;
  }
  size_t start = 0;
  while (true) {
    const size_t end = line.find(sep, start);
    cells.push_back(Trim(line.substr(start, end == std::string_view::npos ? line.npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return cells;
}

bool ParseNumber(const std::string& cell, double* value) {
  const std::string t = Trim(cell);
  if (t.empty()) return false;
  const char* begin = t.data();
  if (*begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, t.data() + t.size(), *value);
  if (ec == std::errc() && ptr == t.data() + t.size()) return true;
  const std::string l = Lower(t);
  if (l == "nan" || l == "-nan" || l == "+nan") {
    *value = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  return false;
}

// A header cell "x_undef [mm]" -> name "x_undef", unit "mm".
struct Column {
  std::string written;  // as in the file
  std::string key;      // lower case, no unit, blanks -> '_'
  std::string unit;     // "" when none
};

Column ParseColumn(const std::string& cell) {
  Column c;
  c.written = Trim(cell);
  std::string name = c.written;
  for (auto [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const size_t a = name.find(open), b = name.rfind(close);
    if (a != std::string::npos && b != std::string::npos && b > a) {
      c.unit = Trim(name.substr(a + 1, b - a - 1));
      name = name.substr(0, a);
      break;
    }
  }
  name = Lower(Trim(name));
  for (char& ch : name)
    if (ch == ' ' || ch == '-') ch = '_';
  c.key = name;
  return c;
}

int FindColumn(const std::vector<Column>& cols, std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    for (size_t i = 0; i < cols.size(); ++i)
      if (cols[i].key == k) return static_cast<int>(i);
  return -1;
}

std::string NormalizeUnit(const std::string& unit, double* m_per_unit, const std::string& name,
                          const std::string& column) {
  try {
    return NormalizeFieldUnit(unit, m_per_unit);
  } catch (const Error& e) {
    throw e.WithContext({.file = name, .field = column});
  }
}

void Push(DisplacementField* f, double x, double y, double u, double v, bool ok) {
  f->x.push_back(x);
  f->y.push_back(y);
  f->u.push_back(std::isfinite(u) ? u : 0.0);
  f->v.push_back(std::isfinite(v) ? v : 0.0);
  f->zncc.push_back(ok ? 1.0 : 0.0);
  f->iterations.push_back(0);
  f->status.push_back(ok ? PointStatus::kOk : PointStatus::kNoConvergence);
}

void Finish(FieldFile* out, const std::string& name) {
  DisplacementField& f = out->field;
  if (f.x.empty())
    throw Error(ErrorKind::kInput, "no data rows", {.file = name, .expected = "one row per point"});
  const size_t n = f.x.size();
  f.nx = static_cast<int>(n);
  f.ny = 1;
  f.dudx.assign(n, 0);
  f.dudy.assign(n, 0);
  f.dvdx.assign(n, 0);
  f.dvdy.assign(n, 0);
  size_t ok = 0;
  for (PointStatus s : f.status) ok += s == PointStatus::kOk ? 1 : 0;
  out->failed = n - ok;
  ArrangeAsGrid(&f);
  if (ok == 0)
    throw Error(ErrorKind::kInput, "every point is marked failed", {.file = name});
}

// A named-column table: rows from `first_row`, cells split on `sep`.
// `default_unit` applies where the header has none (DICe: px).
FieldFile ReadTable(const std::vector<std::string_view>& lines, size_t header_line, char sep,
                    const std::string& header, const std::string& name,
                    const std::string& default_unit, FieldFormat format) {
  std::vector<Column> cols;
  for (const std::string& cell : Split(header, sep)) cols.push_back(ParseColumn(cell));
  // The reference position: a column named as such wins over a bare "x"
  // (which some exports give the deformed position beside x_undef).
  const int ix = FindColumn(cols, {"x_undef", "x_ref", "coordinate_x", "x0", "pos_x", "x"});
  const int iy = FindColumn(cols, {"y_undef", "y_ref", "coordinate_y", "y0", "pos_y", "y"});
  const int iu = FindColumn(cols, {"u", "displacement_x", "ux", "u_x", "disp_x", "dx"});
  const int iv = FindColumn(cols, {"v", "displacement_y", "uy", "u_y", "disp_y", "dy"});
  const int isigma = FindColumn(cols, {"sigma"});
  const int ivalid = FindColumn(cols, {"valid"});
  const std::pair<int, const char*> need[] = {{ix, "x"}, {iy, "y"}, {iu, "u"}, {iv, "v"}};
  for (const auto& [index, role] : need)
    if (index < 0)
      throw Error(ErrorKind::kInput, fmt::format("no {} column in the header", role),
                  {.file = name, .line = static_cast<int>(header_line + 1), .field = role,
                   .value = header.substr(0, 200),
                   .expected = fmt::format("a column named e.g. '{0} [mm]' ({1})", role,
                                           format == FieldFormat::kDice ? "DICe: COORDINATE_X/Y, DISPLACEMENT_X/Y"
                                           : format == FieldFormat::kAramis ? "Aramis: x_undef, y_undef, u, v"
                                                                            : "x, y, u, v")});
  FieldFile out;
  out.format = format;
  std::string unit_seen;
  for (const auto& [index, role] : need) {
    const Column& c = cols[index];
    std::string unit = c.unit.empty() ? default_unit : c.unit;
    if (unit.empty())
      throw Error(ErrorKind::kInput, "column has no unit",
                  {.file = name, .line = static_cast<int>(header_line + 1), .field = c.written,
                   .expected = fmt::format("'{} [mm]' or '{} [px]'", c.key, c.key)});
    double m = 0;
    unit = NormalizeUnit(unit, &m, name, c.written);
    if (unit_seen.empty()) {
      unit_seen = unit;
      out.unit = unit;
      out.m_per_unit = m;
    } else if (unit != unit_seen) {
      throw Error(ErrorKind::kInput, "mixed units: x, y, u and v must share one unit",
                  {.file = name, .line = static_cast<int>(header_line + 1), .field = c.written,
                   .value = unit, .expected = unit_seen});
    }
  }
  const size_t width = cols.size();
  for (size_t li = header_line + 1; li < lines.size(); ++li) {
    const std::string_view line = lines[li];
    if (Trim(line).empty() || line.front() == '#') continue;
    const std::vector<std::string> cells = Split(line, sep);
    if (cells.size() < width)
      throw Error(ErrorKind::kInput, fmt::format("row has {} cells, the header {}", cells.size(), width),
                  {.file = name, .line = static_cast<int>(li + 1)});
    double val[4];
    for (int k = 0; k < 4; ++k)
      if (!ParseNumber(cells[need[k].first], &val[k]))
        throw Error(ErrorKind::kInput, "not a number",
                    {.file = name, .line = static_cast<int>(li + 1),
                     .field = cols[need[k].first].written, .value = cells[need[k].first].substr(0, 40),
                     .expected = "a number"});
    bool ok = std::isfinite(val[0]) && std::isfinite(val[1]) && std::isfinite(val[2]) &&
              std::isfinite(val[3]);
    double flag;
    if (isigma >= 0 && ParseNumber(cells[isigma], &flag) && flag < 0) ok = false;
    if (ivalid >= 0 && ParseNumber(cells[ivalid], &flag) && flag == 0) ok = false;
    Push(&out.field, val[0], val[1], val[2], val[3], ok);
  }
  Finish(&out, name);
  return out;
}

FieldFile ReadDavis(const std::vector<std::string_view>& lines, const std::string& name) {
  // #DaVis 8.4.0 2D-vector 12 17 17 "" "pixel" "" "pixel" "displacement" "pixel"
  const std::string head(lines[0]);
  std::vector<std::string> quoted;
  for (size_t a = head.find('"'); a != std::string::npos;) {
    const size_t b = head.find('"', a + 1);
    if (b == std::string::npos) break;
    quoted.push_back(head.substr(a + 1, b - a - 1));
    a = head.find('"', b + 1);
  }
  const std::vector<std::string> words = Split(head.substr(0, head.find('"')), ' ');
  if (words.size() < 3 || Lower(words[2]) != "2d-vector")
    throw Error(ErrorKind::kInput, "not a DaVis 2D vector file",
                {.file = name, .line = 1, .value = head.substr(0, 80),
                 .expected = "'#DaVis <version> 2D-vector <step> <ny> <nx> ...'"});
  if (quoted.size() < 6)
    throw Error(ErrorKind::kInput, "DaVis header without the units of x, y and the displacement",
                {.file = name, .line = 1, .value = head.substr(0, 120),
                 .expected = "\"\" \"<unit x>\" \"\" \"<unit y>\" \"displacement\" \"<unit>\""});
  FieldFile out;
  out.format = FieldFormat::kDavis;
  double mx = 0, my = 0, mu = 0;
  const std::string ux = NormalizeUnit(quoted[1], &mx, name, "x");
  const std::string uy = NormalizeUnit(quoted[3], &my, name, "y");
  const std::string uu = NormalizeUnit(quoted[5], &mu, name, quoted[4].empty() ? "u" : quoted[4]);
  if (ux != uy || ux != uu)
    throw Error(ErrorKind::kInput, "mixed units: x, y and the displacement must share one unit",
                {.file = name, .line = 1, .field = "displacement", .value = uu, .expected = ux});
  out.unit = ux;
  out.m_per_unit = mx;
  for (size_t li = 1; li < lines.size(); ++li) {
    if (Trim(lines[li]).empty()) continue;
    const std::vector<std::string> cells = Split(lines[li], ' ');
    if (cells.size() < 4)
      throw Error(ErrorKind::kInput, "DaVis row needs x, y, u, v",
                  {.file = name, .line = static_cast<int>(li + 1), .value = std::string(lines[li].substr(0, 80))});
    double val[4];
    const char* roles[4] = {"x", "y", "u", "v"};
    for (int k = 0; k < 4; ++k)
      if (!ParseNumber(cells[k], &val[k]))
        throw Error(ErrorKind::kInput, "not a number",
                    {.file = name, .line = static_cast<int>(li + 1), .field = roles[k],
                     .value = cells[k].substr(0, 40), .expected = "a number"});
    const bool ok = std::isfinite(val[0]) && std::isfinite(val[1]) && std::isfinite(val[2]) &&
                    std::isfinite(val[3]);
    Push(&out.field, val[0], val[1], val[2], val[3], ok);
  }
  Finish(&out, name);
  return out;
}

}  // namespace

FieldFormat DetectFieldFormat(const std::string& text) {
  const size_t probe = std::min<size_t>(text.size(), 1 << 16);
  const std::string head = text.substr(0, probe);
  const std::string first = Lower(Trim(head.substr(0, head.find('\n'))));
  if (first.rfind("#davis", 0) == 0) return FieldFormat::kDavis;
  if (first.rfind("***", 0) == 0) return FieldFormat::kDice;
  if (first.rfind("#", 0) == 0 && head.find(';') != std::string::npos) return FieldFormat::kAramis;
  return FieldFormat::kCsv;
}

FieldFile ReadFieldText(const std::string& text, const std::string& name) {
  if (text.size() > kMaxFieldFileBytes)
    throw Error(ErrorKind::kInput, "field file too large",
                {.file = name, .value = std::to_string(text.size()) + " bytes",
                 .expected = "at most 1 GiB per frame"});
  if (text.size() >= 128 && (text.compare(126, 2, "IM") == 0 || text.compare(126, 2, "MI") == 0))
    throw Error(ErrorKind::kInput, "a MATLAB MAT file is not a text export",
                {.file = name, .expected = "Ncorr MAT files are read as NcorrFile (bridgefit crack takes them as they are)"});
  if (text.find('\0') != std::string::npos)
    throw Error(ErrorKind::kInput, "binary data in a text field file",
                {.file = name, .expected = "a CSV, Aramis nodemap, DICe or DaVis text export"});
  if (Trim(text).empty()) throw Error(ErrorKind::kInput, "empty field file", {.file = name});
  const std::vector<std::string_view> lines = Lines(text);
  const FieldFormat format = DetectFieldFormat(text);
  switch (format) {
    case FieldFormat::kDavis: return ReadDavis(lines, name);
    case FieldFormat::kDice:
      for (size_t i = 0; i < lines.size(); ++i) {
        const std::string t = Trim(lines[i]);
        if (t.empty() || t.rfind("***", 0) == 0) continue;
        return ReadTable(lines, i, ',', t, name, "px", format);
      }
      break;
    case FieldFormat::kAramis: {
      // The header is the last '#' line before the data that has ';' columns.
      size_t header = lines.size();
      for (size_t i = 0; i < lines.size(); ++i) {
        const std::string t = Trim(lines[i]);
        if (t.empty()) continue;
        if (t.front() != '#') break;
        if (t.find(';') != std::string::npos) header = i;
      }
      if (header == lines.size()) break;
      const std::string h = Trim(Trim(lines[header]).substr(1));
      return ReadTable(lines, header, ';', h, name, "", format);
    }
    case FieldFormat::kNcorr:  // binary: refused above
      break;
    case FieldFormat::kCsv:
      for (size_t i = 0; i < lines.size(); ++i) {
        const std::string t = Trim(lines[i]);
        if (t.empty() || t.front() == '#') continue;
        return ReadTable(lines, i, ',', t, name, "", format);
      }
      break;
  }
  throw Error(ErrorKind::kInput, fmt::format("no header line ({} export)", FieldFormatName(format)),
              {.file = name, .expected = "a header naming the x, y, u and v columns"});
}

FieldFile ReadFieldFile(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec)
    throw Error(ErrorKind::kInput, "cannot read field file", {.file = path.string(), .value = ec.message()});
  if (size > kMaxFieldFileBytes)
    throw Error(ErrorKind::kInput, "field file too large",
                {.file = path.string(), .value = std::to_string(size) + " bytes",
                 .expected = "at most 1 GiB per frame"});
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::kInput, "cannot open field file", {.file = path.string()});
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<size_t>(in.gcount()));
  return ReadFieldText(text, path.string());
}

double PointSpacing(const DisplacementField& f) {
  // Median over valid points of the distance to the nearest other point,
  // found on a coarse bucket grid. Exact repeats of a point are left out
  // first: a point whose only neighbours are its repeats made the ring
  // search scan the whole grid (found by fuzzing).
  std::vector<size_t> idx;
  for (size_t i = 0; i < f.size(); ++i)
    if (f.ok(i)) idx.push_back(i);
  std::sort(idx.begin(), idx.end(), [&f](size_t a, size_t b) {
    return f.x[a] != f.x[b] ? f.x[a] < f.x[b] : f.y[a] < f.y[b];
  });
  idx.erase(std::unique(idx.begin(), idx.end(),
                        [&f](size_t a, size_t b) { return f.x[a] == f.x[b] && f.y[a] == f.y[b]; }),
            idx.end());
  if (idx.size() < 2) return 0;
  // The valid points' box (their repeats left out above do not change it).
  const FieldExtent box = ValidExtent(f);
  const double xmin = box.x0, xmax = box.x1, ymin = box.y0, ymax = box.y1;
  // Buckets of about four points each; a field on one line (zero area) gets
  // at most 4n buckets along it. Coordinates whose span overflows have no
  // meaningful spacing.
  const double span = std::max(xmax - xmin, ymax - ymin);
  if (!std::isfinite(span)) return 0;
  const double n = static_cast<double>(idx.size());
  const double cell = std::max({std::sqrt((xmax - xmin) * (ymax - ymin) / n) * 2, span / (4 * n),
                                1e-12});
  const int gx = std::max(1, static_cast<int>((xmax - xmin) / cell) + 1);
  const int gy = std::max(1, static_cast<int>((ymax - ymin) / cell) + 1);
  std::vector<std::vector<size_t>> buckets(static_cast<size_t>(gx) * gy);
  auto bx = [&](double x) { return std::clamp(static_cast<int>((x - xmin) / cell), 0, gx - 1); };
  auto by = [&](double y) { return std::clamp(static_cast<int>((y - ymin) / cell), 0, gy - 1); };
  for (size_t i : idx) buckets[static_cast<size_t>(by(f.y[i])) * gx + bx(f.x[i])].push_back(i);
  std::vector<double> nearest;
  const size_t stride = std::max<size_t>(1, idx.size() / 2000);  // a sample is enough
  for (size_t k = 0; k < idx.size(); k += stride) {
    const size_t i = idx[k];
    double best = 1e300;
    const int cx = bx(f.x[i]), cy = by(f.y[i]);
    // Rings of buckets until a neighbour is found and no closer one can be
    // further out.
    for (int ring = 1; ring <= std::max(gx, gy); ++ring) {
      // The ring's own cells only (8 ring of them; ring 1 includes the centre).
      for (int dy = -ring; dy <= ring; ++dy)
        for (int dx = -ring; dx <= ring; dx += (ring > 1 && std::abs(dy) != ring) ? 2 * ring : 1) {
          const int X = cx + dx, Y = cy + dy;
          if (X < 0 || Y < 0 || X >= gx || Y >= gy) continue;
          for (size_t j : buckets[static_cast<size_t>(Y) * gx + X]) {
            if (j == i) continue;
            const double d = std::hypot(f.x[j] - f.x[i], f.y[j] - f.y[i]);
            if (d > 0) best = std::min(best, d);
          }
        }
      if (best <= (ring - 0.5) * cell) break;
    }
    if (best < 1e300) nearest.push_back(best);
  }
  if (nearest.empty()) return 0;
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

}  // namespace bridgefit::dic

namespace bridgefit::dic {

std::vector<std::filesystem::path> ExpandFieldArguments(const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  auto is_field = [](const fs::path& p) {
    const std::string ext = Lower(p.extension().string());
    return ext == ".txt" || ext == ".csv" || ext == ".dat" || ext == ".mat";
  };
  auto sort_natural = [](std::vector<fs::path>& v) {
    std::sort(v.begin(), v.end(), [](const fs::path& a, const fs::path& b) {
      return NaturalLess(a.filename().string(), b.filename().string());
    });
  };
  std::vector<fs::path> out;
  std::error_code ec;
  for (const std::string& arg : args) {
    const fs::path p(arg);
    std::vector<fs::path> files;
    if (fs::is_directory(p, ec)) {
      for (const auto& entry : fs::directory_iterator(p, ec))
        if (entry.is_regular_file(ec) && is_field(entry.path())) files.push_back(entry.path());
      if (files.empty())
        throw Error(ErrorKind::kInput, "folder holds no field files",
                    {.file = arg, .expected = ".txt, .csv or .dat exports or Ncorr .mat files"});
    } else if (arg.find_first_of("*?[") != std::string::npos && !fs::exists(p, ec)) {
      const fs::path folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
      const std::string pattern = p.filename().string();
      if (fs::is_directory(folder, ec))
        for (const auto& entry : fs::directory_iterator(folder, ec))
          if (entry.is_regular_file(ec) &&
              fnmatch(pattern.c_str(), entry.path().filename().c_str(), 0) == 0)
            files.push_back(entry.path());
      if (files.empty()) throw Error(ErrorKind::kInput, "no file matches the pattern", {.file = arg});
    } else {
      if (!fs::is_regular_file(p, ec)) throw Error(ErrorKind::kInput, "field file not found", {.file = arg});
      files.push_back(p);
    }
    sort_natural(files);
    out.insert(out.end(), files.begin(), files.end());
  }
  if (out.empty()) throw Error(ErrorKind::kInput, "no field files given");
  return out;
}

}  // namespace bridgefit::dic

namespace bridgefit::dic {

bool IsMatFile(const std::filesystem::path& path) {
  // A 128-byte header: text, then the version (0x0100 v5, 0x0200 v7.3) and
  // the endian indicator "IM" (or "MI") in bytes 124-127.
  std::ifstream in(path, std::ios::binary);
  char head[128] = {};
  in.read(head, 128);
  if (in.gcount() != 128) return false;
  const std::string tag(head + 126, 2);
  return tag == "IM" || tag == "MI";
}

FieldFrames::FieldFrames(std::vector<std::filesystem::path> files) : files_(std::move(files)) {}
FieldFrames::~FieldFrames() = default;

bool FieldFrames::Next(FieldFile* frame, std::string* name) {
  while (file_ < files_.size()) {
    const std::filesystem::path& path = files_[file_];
    if (!mat_ && frame_ == 0) {
      if (IsMatFile(path)) {
        mat_ = std::make_unique<NcorrFile>(path);
      } else if (Lower(path.extension().string()) == ".mat") {
        throw Error(ErrorKind::kInput, "not a MATLAB MAT file (no MAT header)",
                    {.file = path.string(), .expected = "Ncorr's saved analysis (MAT v5, v7 or v7.3)"});
      }
    }
    if (mat_) {
      if (frame_ < mat_->Frames()) {
        *frame = mat_->Frame(frame_);
        *name = mat_->FrameName(frame_);
        ++frame_;
        return true;
      }
      mat_.reset();
      frame_ = 0;
      ++file_;
      continue;
    }
    *frame = ReadFieldFile(path);
    *name = path.string();
    ++file_;
    return true;
  }
  return false;
}

}  // namespace bridgefit::dic
