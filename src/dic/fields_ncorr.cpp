// Ncorr's saved analysis (MATLAB MAT v5 or v7.3) read and written with
// matio; matio stays in this file. See include/bridgefit/dic/fields.hpp.
//
// Layout (Ncorr 1.2, ncorr.m, "Save data"): variable data_dic_save, a struct
// with
//   displacements(k): plot_u_ref_formatted, plot_v_ref_formatted (reduced
//                     grid, rows = y, in dispinfo.units, 0 outside the ROI),
//                     roi_ref_formatted (an ncorr_class_roi object in Ncorr's
//                     own files; a struct with a logical `mask` where users
//                     or tools re-saved it as one), plot_u_dic, ...
//   dispinfo:         spacing (grid step = spacing + 1 px), pixtounits (units
//                     per pixel), units (text; "pixels" when not set), ...
#include <matio.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"

namespace bridgefit::dic {
namespace {

constexpr const char* kRoot = "data_dic_save";

// matio's default logger aborts the process on an error message; every
// matio call here reports failure through its return value instead.
void QuietMatioLog(int, char*) {}
void SilenceMatio() {
  static std::once_flag once;
  std::call_once(once, [] { Mat_LogInitFunc("bridgefit", QuietMatioLog); });
}

struct VarDeleter {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};
using VarPtr = std::unique_ptr<matvar_t, VarDeleter>;
struct MatDeleter {
  void operator()(mat_t* m) const { Mat_Close(m); }
};
using MatPtr = std::unique_ptr<mat_t, MatDeleter>;

// The product of the dimensions; SIZE_MAX where it overflows (a corrupt
// header).
size_t Elements(const matvar_t* v) {
  size_t n = 1;
  for (int i = 0; i < v->rank; ++i) {
    if (v->dims[i] != 0 && n > SIZE_MAX / v->dims[i]) return SIZE_MAX;
    n *= v->dims[i];
  }
  return n;
}

// True when the variable's data holds every element it claims: a corrupt
// file's header can claim more than matio read (fuzz_ncorr).
bool DataCovers(const matvar_t* v, size_t element_bytes) {
  const size_t n = Elements(v);
  return v->data != nullptr && element_bytes > 0 && n != SIZE_MAX && n <= v->nbytes / element_bytes;
}

bool IsNumeric(const matvar_t* v) {
  switch (v->class_type) {
    case MAT_C_DOUBLE: case MAT_C_SINGLE: case MAT_C_INT8: case MAT_C_UINT8:
    case MAT_C_INT16: case MAT_C_UINT16: case MAT_C_INT32: case MAT_C_UINT32:
    case MAT_C_INT64: case MAT_C_UINT64:
      return !v->isComplex && DataCovers(v, Mat_SizeOfClass(v->class_type));
    default:
      return false;
  }
}

// Element i of a real numeric variable as a double.
double At(const matvar_t* v, size_t i) {
  switch (v->class_type) {
    case MAT_C_DOUBLE: return static_cast<const double*>(v->data)[i];
    case MAT_C_SINGLE: return static_cast<const float*>(v->data)[i];
    case MAT_C_INT8: return static_cast<const int8_t*>(v->data)[i];
    case MAT_C_UINT8: return static_cast<const uint8_t*>(v->data)[i];
    case MAT_C_INT16: return static_cast<const int16_t*>(v->data)[i];
    case MAT_C_UINT16: return static_cast<const uint16_t*>(v->data)[i];
    case MAT_C_INT32: return static_cast<const int32_t*>(v->data)[i];
    case MAT_C_UINT32: return static_cast<const uint32_t*>(v->data)[i];
    case MAT_C_INT64: return static_cast<double>(static_cast<const int64_t*>(v->data)[i]);
    case MAT_C_UINT64: return static_cast<double>(static_cast<const uint64_t*>(v->data)[i]);
    default: return std::nan("");
  }
}

std::string ClassName(const matvar_t* v) {
  switch (v->class_type) {
    case MAT_C_STRUCT: return "struct";
    case MAT_C_CELL: return "cell";
    case MAT_C_CHAR: return "char";
    case MAT_C_OBJECT: case MAT_C_OPAQUE: return "object";
    case MAT_C_SPARSE: return "sparse";
    case MAT_C_FUNCTION: return "function";
    case MAT_C_EMPTY: return "empty";
    default: return IsNumeric(v) ? "numeric" : "unreadable data";
  }
}

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void Fail(const std::string& message, const std::string& variable,
                         const std::string& value = "", const std::string& expected = "") const {
    throw Error(ErrorKind::kInput, message,
                {.file = file_, .field = variable, .value = value, .expected = expected});
  }

  // Field `name` of element `index` of struct `parent` (named `path`), or
  // null where the struct has no such field. matio's own lookup trusts the
  // struct's field table and data, which a corrupt file can leave short or
  // null (fuzz_ncorr: a SEGV in Mat_VarGetStructFieldByName): both are
  // checked here first, and a corrupt struct is an Error naming it.
  matvar_t* OptionalField(matvar_t* parent, const std::string& path, const char* name,
                          size_t index) const {
    if (!parent || parent->class_type != MAT_C_STRUCT) return nullptr;
    const unsigned fields = Mat_VarGetNumberOfFields(parent);
    char* const* names = Mat_VarGetStructFieldnames(parent);
    if (fields == 0 || !names) return nullptr;
    if (index >= Elements(parent) || !DataCovers(parent, fields * sizeof(matvar_t*)))
      Fail("corrupt struct (its fields were not all read)", path, "",
           "an Ncorr 'Save data' file (ncorr.m 1.2)");
    for (unsigned i = 0; i < fields; ++i)
      if (names[i] && std::strcmp(names[i], name) == 0)
        return static_cast<matvar_t**>(parent->data)[index * fields + i];
    return nullptr;
  }

  matvar_t* Field(matvar_t* parent, const std::string& path, const char* name, size_t index) const {
    matvar_t* f = OptionalField(parent, path, name, index);
    if (!f) Fail("missing variable", path + "." + name, "", "an Ncorr 'Save data' file (ncorr.m 1.2)");
    return f;
  }

  const matvar_t* Matrix(matvar_t* parent, const std::string& path, const char* name,
                         size_t index) const {
    const matvar_t* m = Field(parent, path, name, index);
    const std::string where = path + "." + name;
    if (!IsNumeric(m) || m->rank != 2 || Elements(m) == 0)
      Fail("not a real numeric matrix", where, ClassName(m), "a 2-D matrix of displacements");
    return m;
  }

  double Scalar(matvar_t* parent, const std::string& path, const char* name) const {
    const matvar_t* s = Field(parent, path, name, 0);
    const std::string where = path + "." + name;
    if (!IsNumeric(s) || Elements(s) != 1) Fail("not a number", where, ClassName(s), "a scalar");
    const double value = At(s, 0);
    if (!std::isfinite(value)) Fail("not a finite number", where, fmt::format("{}", value), "a finite scalar");
    return value;
  }

  std::string Text(matvar_t* parent, const std::string& path, const char* name) const {
    const matvar_t* s = Field(parent, path, name, 0);
    const std::string where = path + "." + name;
    if (s->class_type != MAT_C_CHAR) Fail("not text", where, ClassName(s), "a character array");
    if (!s->data) return "";
    std::string out;
    const size_t n = Elements(s);
    const size_t width = s->data_size > 0 ? s->data_size : 1;
    if (!DataCovers(s, width) || n > 4096)
      Fail("corrupt or overlong text", where, "", "a short character array");
    for (size_t i = 0; i < n; ++i) {
      const auto* bytes = static_cast<const unsigned char*>(s->data) + i * width;
      unsigned code = bytes[0];
      if (width == 2) code = static_cast<unsigned>(bytes[0] | (bytes[1] << 8));
      out += code < 128 ? static_cast<char>(code) : '?';
    }
    return out;
  }

 private:
  std::string file_;
};

}  // namespace

struct NcorrFile::Impl {
  std::string file;
  MatPtr mat;
  VarPtr root;
  matvar_t* displacements = nullptr;  // owned by root
  size_t frames = 0;
  int spacing = 0;
  double pixtounits = 1;
  std::string unit;         // "px" or a length unit
  double m_per_unit = 0;
  int version = 0;
};

NcorrFile::NcorrFile(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
  SilenceMatio();
  Impl& d = *impl_;
  d.file = path.string();
  const Reader r(d.file);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(ErrorKind::kInput, "Ncorr MAT file not found", {.file = d.file});
  d.mat.reset(Mat_Open(d.file.c_str(), MAT_ACC_RDONLY));
  if (!d.mat)
    throw Error(ErrorKind::kInput, "not a readable MATLAB MAT file",
                {.file = d.file, .expected = "Ncorr's saved analysis (MAT v5, v7 or v7.3)"});
  const mat_ft version = Mat_GetVersion(d.mat.get());
  if (version == MAT_FT_MAT4)
    throw Error(ErrorKind::kInput, "MAT v4 file: Ncorr writes v7.3 (or v5/v7 when re-saved)",
                {.file = d.file, .expected = "a MAT v5, v7 or v7.3 file"});
  d.version = version == MAT_FT_MAT73 ? 73 : 5;
  d.root.reset(Mat_VarRead(d.mat.get(), kRoot));
  if (!d.root)
    r.Fail("no variable data_dic_save (or it cannot be read)", kRoot, "",
           "Ncorr's 'Save data' output, which holds data_dic_save");
  if (d.root->class_type != MAT_C_STRUCT || Elements(d.root.get()) != 1)
    r.Fail("not a 1x1 struct", kRoot, ClassName(d.root.get()), "a struct");
  d.displacements = r.Field(d.root.get(), kRoot, "displacements", 0);
  const std::string dpath = std::string(kRoot) + ".displacements";
  if (d.displacements->class_type != MAT_C_STRUCT)
    r.Fail("not a struct array", dpath, ClassName(d.displacements), "one struct per frame");
  d.frames = Elements(d.displacements);
  if (d.frames == 0) r.Fail("no frames (empty struct array)", dpath, "0", "at least one frame");
  matvar_t* info = r.Field(d.root.get(), kRoot, "dispinfo", 0);
  const std::string ipath = std::string(kRoot) + ".dispinfo";
  if (info->class_type != MAT_C_STRUCT || Elements(info) < 1)
    r.Fail("not a struct", ipath, ClassName(info), "a struct with spacing, pixtounits, units");
  const double spacing = r.Scalar(info, ipath, "spacing");
  if (spacing < 0 || spacing > 1000 || spacing != std::floor(spacing))
    r.Fail("spacing is not a whole number of pixels", ipath + ".spacing", fmt::format("{}", spacing),
           "an integer 0..1000 (grid step = spacing + 1 px)");
  d.spacing = static_cast<int>(spacing);
  d.pixtounits = r.Scalar(info, ipath, "pixtounits");
  if (!(d.pixtounits > 0))
    r.Fail("pixtounits must be positive", ipath + ".pixtounits", fmt::format("{}", d.pixtounits),
           "units per pixel > 0");
  std::string units = r.Text(info, ipath, "units");
  double m = 0;
  try {
    d.unit = NormalizeFieldUnit(units.empty() ? "pixels" : units, &m);
  } catch (const Error& e) {
    throw e.WithContext({.file = d.file, .field = ipath + ".units"});
  }
  d.m_per_unit = m;
  if (m == 0 && std::abs(d.pixtounits - 1) > 1e-12)
    r.Fail("units are pixels but pixtounits is not 1", ipath + ".pixtounits",
           fmt::format("{}", d.pixtounits), "1 for units 'pixels' (or a length unit in units)");
}

NcorrFile::~NcorrFile() = default;
NcorrFile::NcorrFile(NcorrFile&&) noexcept = default;
NcorrFile& NcorrFile::operator=(NcorrFile&&) noexcept = default;

std::size_t NcorrFile::Frames() const { return impl_->frames; }
int NcorrFile::MatVersion() const { return impl_->version; }
int NcorrFile::Spacing() const { return impl_->spacing; }

std::string NcorrFile::FrameName(std::size_t k) const {
  return fmt::format("{}: displacements({})", impl_->file, k + 1);
}

FieldFile NcorrFile::Frame(std::size_t k) const {
  const Impl& d = *impl_;
  if (k >= d.frames)
    throw Error(ErrorKind::kUsage, "frame index out of range",
                {.file = d.file, .value = std::to_string(k + 1),
                 .expected = fmt::format("1..{}", d.frames)});
  const Reader r(d.file);
  const std::string path = fmt::format("{}.displacements({})", kRoot, k + 1);
  const matvar_t* u = r.Matrix(d.displacements, path, "plot_u_ref_formatted", k);
  const matvar_t* v = r.Matrix(d.displacements, path, "plot_v_ref_formatted", k);
  const size_t rows = u->dims[0], cols = u->dims[1];
  if (v->dims[0] != rows || v->dims[1] != cols)
    r.Fail("u and v plots differ in size", path + ".plot_v_ref_formatted",
           fmt::format("{}x{}", v->dims[0], v->dims[1]), fmt::format("{}x{}", rows, cols));
  // The ROI mask where it is a plain struct; Ncorr's own roi objects are
  // opaque to matio: then a node with u = v = 0 exactly is outside the ROI
  // (Ncorr writes zeros there).
  const matvar_t* mask = nullptr;
  if (matvar_t* roi = r.OptionalField(d.displacements, path, "roi_ref_formatted", k);
      roi && roi->class_type == MAT_C_STRUCT && Elements(roi) >= 1) {
    const matvar_t* m = r.OptionalField(roi, path + ".roi_ref_formatted", "mask", 0);
    if (m && IsNumeric(m) && m->rank == 2 && m->dims[0] == rows && m->dims[1] == cols) mask = m;
    else if (m)
      r.Fail("ROI mask differs from the displacement plots", path + ".roi_ref_formatted.mask",
             m->rank == 2 ? fmt::format("{}x{}", m->dims[0], m->dims[1]) : ClassName(m),
             fmt::format("a {}x{} logical matrix", rows, cols));
  }
  FieldFile out;
  out.format = FieldFormat::kNcorr;
  out.unit = d.unit;
  out.m_per_unit = d.m_per_unit;
  DisplacementField& f = out.field;
  const size_t n = rows * cols;
  f.nx = static_cast<int>(cols);
  f.ny = static_cast<int>(rows);
  for (auto* vec : {&f.x, &f.y, &f.u, &f.v, &f.zncc, &f.dudx, &f.dudy, &f.dvdx, &f.dvdy})
    vec->reserve(n);
  const double step = (d.spacing + 1) * (d.m_per_unit > 0 ? d.pixtounits : 1.0);
  // Row-major output (x fastest) from MATLAB's column-major matrices.
  for (size_t row = 0; row < rows; ++row)
    for (size_t col = 0; col < cols; ++col) {
      const size_t i = row + col * rows;
      const double uu = At(u, i), vv = At(v, i);
      bool ok = std::isfinite(uu) && std::isfinite(vv);
      if (mask) ok = ok && At(mask, i) != 0;
      else ok = ok && !(uu == 0 && vv == 0);
      f.x.push_back(static_cast<double>(col) * step);
      f.y.push_back(static_cast<double>(row) * step);
      f.u.push_back(ok ? uu : 0.0);
      f.v.push_back(ok ? vv : 0.0);
      f.zncc.push_back(ok ? 1.0 : 0.0);
      f.iterations.push_back(0);
      f.status.push_back(ok ? PointStatus::kOk : PointStatus::kNoConvergence);
      out.failed += ok ? 0 : 1;
    }
  f.dudx.assign(n, 0);
  f.dudy.assign(n, 0);
  f.dvdx.assign(n, 0);
  f.dvdy.assign(n, 0);
  if (out.failed == n)
    r.Fail("every point of the frame is outside the ROI (or zero)", path + ".plot_u_ref_formatted",
           "", "some displacements inside roi_ref_formatted");
  return out;
}

namespace {

// A MATLAB matrix (column-major) of doubles or a logical one.
VarPtr MakeMatrix(const char* name, size_t rows, size_t cols, const std::vector<double>& values) {
  size_t dims[2] = {rows, cols};
  return VarPtr(Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                              const_cast<double*>(values.data()), 0));
}

VarPtr MakeLogical(const char* name, size_t rows, size_t cols, const std::vector<uint8_t>& values) {
  size_t dims[2] = {rows, cols};
  return VarPtr(Mat_VarCreate(name, MAT_C_UINT8, MAT_T_UINT8, 2, dims,
                              const_cast<uint8_t*>(values.data()), MAT_F_LOGICAL));
}

VarPtr MakeScalar(const char* name, double value) {
  size_t dims[2] = {1, 1};
  return VarPtr(Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, &value, 0));
}

VarPtr MakeText(const char* name, const std::string& text) {
  size_t dims[2] = {1, text.size()};
  return VarPtr(Mat_VarCreate(name, MAT_C_CHAR, MAT_T_UTF8, 2, dims,
                              const_cast<char*>(text.data()), 0));
}

// Sets a field of a struct built here; the struct owns the value after.
void SetField(matvar_t* s, const char* name, size_t index, VarPtr value) {
  if (!value) throw Error(ErrorKind::kRuntime, "cannot build the MAT variable", {.field = name});
  matvar_t* previous = Mat_VarSetStructFieldByName(s, name, index, value.release());
  if (previous) Mat_VarFree(previous);
}

struct GridFrame {
  size_t rows = 0, cols = 0;
  std::vector<double> u, v;     // column-major
  std::vector<uint8_t> mask;
};

// Nodes of `f` on the Ncorr grid: x = col * step, y = row * step (step in
// the field's unit), col, row >= 0.
GridFrame ToGrid(const DisplacementField& f, double step, size_t frame) {
  GridFrame g;
  std::vector<long> cols(f.size()), rows(f.size());
  for (size_t i = 0; i < f.size(); ++i) {
    const double c = f.x[i] / step, r = f.y[i] / step;
    if (!(std::abs(c - std::round(c)) < 1e-6 && std::abs(r - std::round(r)) < 1e-6 && c > -0.5 &&
          r > -0.5))
      throw Error(ErrorKind::kUsage, "point is not on the Ncorr grid",
                  {.field = fmt::format("frame {} point {}", frame + 1, i),
                   .value = fmt::format("({}, {})", f.x[i], f.y[i]),
                   .expected = fmt::format("x, y >= 0 on multiples of the grid step {}", step)});
    cols[i] = std::lround(c);
    rows[i] = std::lround(r);
    g.cols = std::max(g.cols, static_cast<size_t>(cols[i]) + 1);
    g.rows = std::max(g.rows, static_cast<size_t>(rows[i]) + 1);
  }
  g.u.assign(g.rows * g.cols, 0.0);
  g.v.assign(g.rows * g.cols, 0.0);
  g.mask.assign(g.rows * g.cols, 0);
  for (size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    const size_t k = static_cast<size_t>(rows[i]) + static_cast<size_t>(cols[i]) * g.rows;
    g.u[k] = f.u[i];
    g.v[k] = f.v[i];
    g.mask[k] = 1;
  }
  return g;
}

}  // namespace

void WriteNcorrFile(const std::filesystem::path& path, const std::vector<FieldFile>& frames,
                    const NcorrWriteOptions& options) {
  SilenceMatio();
  if (frames.empty()) throw Error(ErrorKind::kUsage, "no frames to write", {.file = path.string()});
  if (options.spacing_px < 0)
    throw Error(ErrorKind::kUsage, "Ncorr spacing must be >= 0",
                {.field = "spacing", .value = std::to_string(options.spacing_px)});
  const FieldFile& first = frames.front();
  const double step = PointSpacing(first.field);
  if (!(step > 0))
    throw Error(ErrorKind::kUsage, "cannot tell the grid step of the first frame", {.file = path.string()});
  const double pixtounits = first.IsPixels() ? 1.0 : step / (options.spacing_px + 1);
  if (first.IsPixels() && std::abs(step - (options.spacing_px + 1)) > 1e-9)
    throw Error(ErrorKind::kUsage, "a field in px must have a grid step of spacing + 1 px",
                {.field = "spacing", .value = fmt::format("step {} px", step),
                 .expected = fmt::format("spacing = {}", step - 1)});
  std::vector<GridFrame> grids;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (frames[k].unit != first.unit)
      throw Error(ErrorKind::kUsage, "frames with different units",
                  {.field = fmt::format("frame {}", k + 1), .value = frames[k].unit, .expected = first.unit});
    grids.push_back(ToGrid(frames[k].field, step, k));
  }
  const char* disp_fields[] = {"plot_u_ref_formatted", "plot_v_ref_formatted", "roi_ref_formatted"};
  size_t ddims[2] = {1, frames.size()};
  VarPtr disp(Mat_VarCreateStruct("displacements", 2, ddims, disp_fields, options.roi_mask ? 3 : 2));
  for (size_t k = 0; k < grids.size(); ++k) {
    const GridFrame& g = grids[k];
    SetField(disp.get(), "plot_u_ref_formatted", k, MakeMatrix("plot_u_ref_formatted", g.rows, g.cols, g.u));
    SetField(disp.get(), "plot_v_ref_formatted", k, MakeMatrix("plot_v_ref_formatted", g.rows, g.cols, g.v));
    if (!options.roi_mask) continue;
    const char* roi_fields[] = {"mask"};
    size_t one[2] = {1, 1};
    VarPtr roi(Mat_VarCreateStruct("roi_ref_formatted", 2, one, roi_fields, 1));
    SetField(roi.get(), "mask", 0, MakeLogical("mask", g.rows, g.cols, g.mask));
    SetField(disp.get(), "roi_ref_formatted", k, std::move(roi));
  }
  const char* info_fields[] = {"type", "spacing", "pixtounits", "units"};
  size_t one[2] = {1, 1};
  VarPtr info(Mat_VarCreateStruct("dispinfo", 2, one, info_fields, 4));
  SetField(info.get(), "type", 0, MakeText("type", "regular"));
  SetField(info.get(), "spacing", 0, MakeScalar("spacing", options.spacing_px));
  SetField(info.get(), "pixtounits", 0, MakeScalar("pixtounits", pixtounits));
  SetField(info.get(), "units", 0, MakeText("units", first.IsPixels() ? "pixels" : first.unit));
  const char* root_fields[] = {"displacements", "dispinfo"};
  VarPtr root(Mat_VarCreateStruct(kRoot, 2, one, root_fields, 2));
  SetField(root.get(), "displacements", 0, std::move(disp));
  SetField(root.get(), "dispinfo", 0, std::move(info));

  AtomicOutput output(path);
  {
    MatPtr mat(Mat_CreateVer(output.temporary_path().c_str(), nullptr,  // "MATLAB 5.0/7.3 MAT-file, ..."
                             options.v73 ? MAT_FT_MAT73 : MAT_FT_MAT5));
    if (!mat) throw Error(ErrorKind::kRuntime, "cannot create MAT file", {.file = path.string()});
    if (Mat_VarWrite(mat.get(), root.get(), MAT_COMPRESSION_ZLIB) != 0)
      throw Error(ErrorKind::kRuntime, "cannot write MAT variable", {.file = path.string(), .field = kRoot});
  }
  output.Commit();
}

void ReadEveryNcorrFrame(const std::filesystem::path& path) {
  const NcorrFile ncorr(path);
  for (std::size_t k = 0; k < ncorr.Frames(); ++k) (void)ncorr.Frame(k);
}

}  // namespace bridgefit::dic
