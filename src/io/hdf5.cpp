#include "bridgefit/io/hdf5.hpp"

#include <H5Cpp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>
#include <optional>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/version.hpp"
#include "hdf5_checked.hpp"

namespace bridgefit::io {
namespace {

H5::StrType VariableString() {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  return type;
}

std::vector<std::string> SplitPath(const std::string& path) {
  std::vector<std::string> parts;
  std::string part;
  for (char c : path) {
    if (c == '/') {
      if (!part.empty()) parts.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  if (!part.empty()) parts.push_back(part);
  return parts;
}

std::string ParentOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == 0 || slash == std::string::npos ? "/" : path.substr(0, slash);
}

[[noreturn]] void Fail(const std::string& file, const std::string& what, const H5::Exception& e) {
  throw Error(ErrorKind::kRuntime, what + ": " + e.getDetailMsg(), {.file = file});
}

void SetStringAttribute(H5::H5Object& object, const std::string& key, const std::string& value) {
  if (object.attrExists(key)) object.removeAttr(key);
  const H5::StrType type = VariableString();
  H5::Attribute attribute = object.createAttribute(key, type, H5::DataSpace(H5S_SCALAR));
  const char* data = value.c_str();
  attribute.write(type, &data);
}

void SetNumberAttribute(H5::H5Object& object, const std::string& key, double value) {
  if (object.attrExists(key)) object.removeAttr(key);
  H5::Attribute attribute =
      object.createAttribute(key, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
  attribute.write(H5::PredType::NATIVE_DOUBLE, &value);
}

// Calls f(H5::H5Object&) on the group or dataset at `path`.
template <class F>
auto VisitObject(H5::H5File& file, const std::string& path, F&& f) {
  if (path != "/" && !path.empty() && file.childObjType(path) == H5O_TYPE_DATASET) {
    H5::DataSet dataset = file.openDataSet(path);
    return f(static_cast<H5::H5Object&>(dataset));
  }
  H5::Group group = file.openGroup(path.empty() ? "/" : path);
  return f(static_cast<H5::H5Object&>(group));
}

}  // namespace

// ---- Writer ---------------------------------------------------------------

struct H5Writer::Impl {
  std::filesystem::path target;
  std::unique_ptr<AtomicOutput> output;
  std::unique_ptr<H5::H5File> file;

  void EnsureGroup(const std::string& path) {
    std::string current;
    for (const std::string& part : SplitPath(path)) {
      current += "/" + part;
      if (!file->nameExists(current)) file->createGroup(current);
    }
  }

  // Calls f on the group or dataset at `path`; a missing path becomes a group.
  template <class F>
  void WithObject(const std::string& path, F&& f) {
    if (path != "/" && !path.empty()) EnsureGroup(path);  // creates only what is missing
    VisitObject(*file, path, f);
  }

  H5::DataSet CreateDouble(const std::string& path, const std::vector<hsize_t>& dims,
                           const double* data, const std::string& units,
                           const std::string& description) {
    EnsureGroup(ParentOf(path));
    if (file->nameExists(path)) file->unlink(path);
    H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    H5::DataSet dataset = file->createDataSet(path, H5::PredType::NATIVE_DOUBLE, space);
    if (dims[0] > 0) dataset.write(data, H5::PredType::NATIVE_DOUBLE);
    SetStringAttribute(dataset, "units", units);
    if (!description.empty()) SetStringAttribute(dataset, "description", description);
    return dataset;
  }
};

H5Writer::H5Writer(const std::filesystem::path& target) : impl_(std::make_unique<Impl>()) {
  impl_->target = target;
  impl_->output = std::make_unique<AtomicOutput>(target);
  try {
    H5::Exception::dontPrint();
    impl_->file = std::make_unique<H5::H5File>(impl_->output->temporary_path().string(),
                                               H5F_ACC_TRUNC);
    H5::Group root = impl_->file->openGroup("/");
    SetStringAttribute(root, "format", "bridgefit-h5 1 (docs/FORMATS.md)");
    SetStringAttribute(root, "bridgefit_version", VersionString());
    const std::time_t now = std::time(nullptr);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    SetStringAttribute(root, "created_utc", stamp);
  } catch (const H5::Exception& e) {
    Fail(target.string(), "could not create HDF5 file", e);
  }
}

H5Writer::~H5Writer() = default;

void H5Writer::WriteVector(const std::string& path, const std::vector<double>& values,
                           const std::string& units, const std::string& description) {
  try {
    impl_->CreateDouble(path, {values.size()}, values.data(), units, description);
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not write dataset " + path, e);
  }
}

void H5Writer::WriteMatrix(const std::string& path, std::size_t rows, std::size_t cols,
                           const std::vector<double>& values, const std::string& units,
                           const std::string& description) {
  if (values.size() != rows * cols)
    throw Error(ErrorKind::kInternal, "matrix size mismatch for " + path);
  try {
    impl_->CreateDouble(path, {rows, cols}, values.data(), units, description);
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not write dataset " + path, e);
  }
}

void H5Writer::WriteStrings(const std::string& path, const std::vector<std::string>& values) {
  try {
    impl_->EnsureGroup(ParentOf(path));
    if (impl_->file->nameExists(path)) impl_->file->unlink(path);
    const hsize_t n = values.size();
    H5::DataSpace space(1, &n);
    const H5::StrType type = VariableString();
    H5::DataSet dataset = impl_->file->createDataSet(path, type, space);
    std::vector<const char*> pointers;
    for (const auto& v : values) pointers.push_back(v.c_str());
    if (n > 0) dataset.write(pointers.data(), type);
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not write dataset " + path, e);
  }
}

void H5Writer::WriteAttribute(const std::string& object_path, const std::string& key,
                              const std::string& value) {
  try {
    impl_->WithObject(object_path, [&](H5::H5Object& o) { SetStringAttribute(o, key, value); });
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not write attribute " + object_path + "@" + key, e);
  }
}

void H5Writer::WriteAttribute(const std::string& object_path, const std::string& key,
                              double value) {
  try {
    impl_->WithObject(object_path, [&](H5::H5Object& o) { SetNumberAttribute(o, key, value); });
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not write attribute " + object_path + "@" + key, e);
  }
}

void H5Writer::CopyFileInto(const std::filesystem::path& source, const std::string& dest_group) {
  try {
    H5::H5File in(source.string(), H5F_ACC_RDONLY);
    impl_->EnsureGroup(dest_group);
    const H5::Group root = in.openGroup("/");
    for (hsize_t i = 0; i < root.getNumObjs(); ++i) {
      const std::string name = root.getObjnameByIdx(i);
      const std::string to = dest_group + "/" + name;
      if (impl_->file->nameExists(to)) impl_->file->unlink(to);
      if (H5Ocopy(in.getId(), ("/" + name).c_str(), impl_->file->getId(), to.c_str(), H5P_DEFAULT,
                  H5P_DEFAULT) < 0)
        throw Error(ErrorKind::kRuntime, "could not copy an HDF5 group",
                    {.file = source.string(), .field = "/" + name, .value = to});
    }
  } catch (const H5::Exception& e) {
    Fail(source.string(), "could not copy the file into " + dest_group, e);
  }
}

void H5Writer::Commit() {
  try {
    impl_->file->close();
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not close HDF5 file", e);
  }
  impl_->output->Commit();
}

// ---- Reader ---------------------------------------------------------------
// Layered defence (docs/HOSTILE_INPUT.md): every dataset's extent is checked
// against the file size and the element cap before anything is allocated,
// every attribute's type class and element count before it is read, and
// external or virtual storage (which would read other files) is refused.
// Crashes inside libhdf5 itself are caught one level up, by
// CheckH5FileInChildProcess (hdf5_check.cpp).

namespace {

// Bytes one variable-length element takes in the dataset's own storage
// (length + global-heap address + index): a lower bound on the file size.
constexpr std::uint64_t kVlenReferenceBytes = 16;
// Compression cannot shrink data more than about 1032:1 (deflate's limit).
constexpr std::uint64_t kMaxFilterRatio = 1100;
constexpr std::uint64_t kMaxStringAttributeBytes = 1 << 20;

// A memory string type of `size` with the file type's character set:
// libhdf5 does not convert between ASCII and UTF-8.
H5::StrType MemoryString(const H5::DataType& file_type, std::size_t size) {
  H5::StrType memory(H5::PredType::C_S1, size);
  memory.setCset(H5Tget_cset(file_type.getId()));
  return memory;
}

}  // namespace

H5Checked::H5Checked(std::string file_name, std::uint64_t file_bytes, InputLimits limits)
    : file_(std::move(file_name)), file_bytes_(file_bytes), limits_(limits) {}

Error H5Checked::Refuse(const std::string& field, const std::string& what,
                        const std::string& value, const std::string& expected) const {
  return Error(ErrorKind::kInput, what,
               {.file = file_, .field = field, .value = value, .expected = expected});
}

std::uint64_t H5Checked::CheckedExtent(const H5::DataSet& dataset, const std::string& field,
                                       std::uint64_t stored_element_bytes) const {
  const H5::DataSpace space = dataset.getSpace();
  const H5S_class_t space_class = space.getSimpleExtentType();
  if (space_class == H5S_NULL) return 0;
  const hssize_t points = space.getSimpleExtentNpoints();
  if (points < 0) throw Refuse(field, "dataset has an invalid extent");
  const auto n = static_cast<std::uint64_t>(points);
  const H5::DSetCreatPropList create = dataset.getCreatePlist();
  if (create.getLayout() == H5D_VIRTUAL || create.getExternalCount() > 0)
    throw Refuse(field, "dataset stores its data in other files (external or virtual layout)",
                 "", "data stored inside this file");
  if (n > limits_.max_dataset_elements)
    throw Refuse(field,
                 fmt::format("dataset has {} elements, over the limit of {} ({})", n,
                             limits_.max_dataset_elements, InputLimits::kDatasetElementsVariable),
                 "", fmt::format("at most {} elements; set {} to raise the limit",
                                 limits_.max_dataset_elements,
                                 InputLimits::kDatasetElementsVariable));
  const bool filtered = create.getNfilters() > 0;
  const std::uint64_t allowed = filtered ? file_bytes_ * kMaxFilterRatio : file_bytes_;
  const std::uint64_t element = std::max<std::uint64_t>(stored_element_bytes, 1);
  if (n > allowed / element)
    throw Refuse(field,
                 fmt::format("dataset claims {} elements of {} bytes but the file has only {} "
                             "bytes",
                             n, element, file_bytes_),
                 "", "an intact HDF5 file (this one is truncated or corrupt)");
  return n;
}

std::vector<double> H5Checked::ReadNumbers(const H5::DataSet& dataset,
                                           const std::string& field) const {
  const H5::DataType type = dataset.getDataType();
  const H5T_class_t type_class = type.getClass();
  if (type_class != H5T_FLOAT && type_class != H5T_INTEGER)
    throw Refuse(field, "dataset is not numeric", "", "a dataset of numbers");
  const std::uint64_t n = CheckedExtent(dataset, field, type.getSize());
  std::vector<double> values(n);
  if (n > 0) dataset.read(values.data(), H5::PredType::NATIVE_DOUBLE);
  return values;
}

std::vector<std::string> H5Checked::ReadTexts(const H5::DataSet& dataset,
                                              const std::string& field) const {
  const H5::DataType type = dataset.getDataType();
  if (type.getClass() != H5T_STRING)
    throw Refuse(field, "dataset is not text", "", "a dataset of strings");
  std::vector<std::string> out;
  if (type.isVariableStr()) {
    const std::uint64_t n = CheckedExtent(dataset, field, kVlenReferenceBytes);
    std::vector<char*> pointers(n, nullptr);
    const H5::StrType memory = MemoryString(type, H5T_VARIABLE);
    if (n > 0) dataset.read(pointers.data(), memory);
    out.reserve(n);
    for (char* p : pointers) {
      out.emplace_back(p ? p : "");
      H5free_memory(p);
    }
    return out;
  }
  const std::size_t width = type.getSize();
  const std::uint64_t n = CheckedExtent(dataset, field, width);
  std::vector<char> buffer(n * width + 1, '\0');
  const H5::StrType memory = MemoryString(type, width);
  if (n > 0) dataset.read(buffer.data(), memory);
  for (std::uint64_t i = 0; i < n; ++i) {
    const char* begin = buffer.data() + i * width;
    out.emplace_back(begin, strnlen(begin, width));
  }
  return out;
}

void H5Checked::CheckScalarAttribute(const H5::Attribute& attribute,
                                     const std::string& field) const {
  const H5::DataSpace space = attribute.getSpace();
  const H5S_class_t space_class = space.getSimpleExtentType();
  const hssize_t points = space_class == H5S_NULL ? 0 : space.getSimpleExtentNpoints();
  if (points != 1)
    throw Refuse(field, fmt::format("attribute holds {} values, not one", points), "",
                 "a scalar attribute");
}

std::string H5Checked::ReadTextAttribute(const H5::Attribute& attribute,
                                         const std::string& field) const {
  const H5::DataType type = attribute.getDataType();
  if (type.getClass() != H5T_STRING)
    throw Refuse(field, "attribute is not text", "", "a string attribute");
  CheckScalarAttribute(attribute, field);
  if (type.isVariableStr()) {
    char* pointer = nullptr;
    const H5::StrType memory = MemoryString(type, H5T_VARIABLE);
    attribute.read(memory, &pointer);
    std::string value = pointer ? pointer : "";
    H5free_memory(pointer);
    return value;
  }
  const std::size_t width = type.getSize();
  if (width > kMaxStringAttributeBytes || width > file_bytes_)
    throw Refuse(field, fmt::format("string attribute of {} bytes in a file of {} bytes", width,
                                    file_bytes_));
  // A buffer of exactly one element of the file's width: the read cannot
  // write past it (the H5::Attribute std::string read could, on corrupt sizes).
  std::vector<char> buffer(width + 1, '\0');
  const H5::StrType memory = MemoryString(type, width);
  attribute.read(memory, buffer.data());
  return std::string(buffer.data(), strnlen(buffer.data(), width));
}

double H5Checked::ReadNumberAttribute(const H5::Attribute& attribute,
                                      const std::string& field) const {
  const H5::DataType type = attribute.getDataType();
  const H5T_class_t type_class = type.getClass();
  if (type_class != H5T_FLOAT && type_class != H5T_INTEGER)
    throw Refuse(field, "attribute is not a number", "", "a numeric attribute");
  CheckScalarAttribute(attribute, field);
  double value = 0.0;
  attribute.read(H5::PredType::NATIVE_DOUBLE, &value);
  return value;
}

struct H5Reader::Impl {
  std::string name;
  std::unique_ptr<H5::H5File> file;
  std::unique_ptr<H5Checked> checked;
};

H5Reader::H5Reader(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
  impl_->name = path.string();
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    throw Error(ErrorKind::kInput, "file not found", {.file = impl_->name});
  if (!std::filesystem::is_regular_file(status))
    throw Error(ErrorKind::kInput, "not a regular file",
                {.file = impl_->name, .expected = "an HDF5 file written by bridgefit"});
  const std::uint64_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw Error(ErrorKind::kInput, "cannot read file size", {.file = impl_->name});
  impl_->checked = std::make_unique<H5Checked>(impl_->name, bytes, InputLimits::FromEnvironment());
  H5::Exception::dontPrint();
  try {
    if (!H5::H5File::isHdf5(impl_->name))
      throw Error(ErrorKind::kInput, "not an HDF5 file",
                  {.file = impl_->name, .expected = "an HDF5 file written by bridgefit"});
    impl_->file = std::make_unique<H5::H5File>(impl_->name, H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot open HDF5 file: " + e.getDetailMsg(), {.file = impl_->name});
  }
}

H5Reader::~H5Reader() = default;

bool H5Reader::Exists(const std::string& path) const {
  try {
    std::string current;
    for (const std::string& part : SplitPath(path)) {
      current += "/" + part;
      if (!impl_->file->nameExists(current)) return false;
      H5L_info_t info;
      if (H5Lget_info(impl_->file->getId(), current.c_str(), &info, H5P_DEFAULT) < 0) return false;
      if (info.type == H5L_TYPE_EXTERNAL || info.type >= H5L_TYPE_UD_MIN)
        throw Error(ErrorKind::kInput, "link to another file is not followed",
                    {.file = impl_->name, .field = current,
                     .expected = "groups and datasets inside this file"});
    }
    return true;
  } catch (const H5::Exception&) {
    return false;
  }
}

std::vector<double> H5Reader::ReadVector(const std::string& path, std::string* units) const {
  if (!Exists(path))
    throw Error(ErrorKind::kInput, "missing dataset", {.file = impl_->name, .field = path});
  try {
    const H5::DataSet dataset = impl_->file->openDataSet(path);
    std::vector<double> values = impl_->checked->ReadNumbers(dataset, path);
    if (units) *units = dataset.attrExists("units") ? ReadStringAttribute(path, "units") : "";
    return values;
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot read dataset: " + e.getDetailMsg(),
                {.file = impl_->name, .field = path});
  }
}

std::vector<std::string> H5Reader::ReadStrings(const std::string& path) const {
  if (!Exists(path))
    throw Error(ErrorKind::kInput, "missing dataset", {.file = impl_->name, .field = path});
  try {
    const H5::DataSet dataset = impl_->file->openDataSet(path);
    return impl_->checked->ReadTexts(dataset, path);
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot read dataset: " + e.getDetailMsg(),
                {.file = impl_->name, .field = path});
  }
}

bool H5Reader::HasAttribute(const std::string& object_path, const std::string& key) const {
  if (!Exists(object_path)) return false;
  try {
    return VisitObject(*impl_->file, object_path,
                       [&](H5::H5Object& o) { return o.attrExists(key); });
  } catch (const H5::Exception&) {
    return false;
  }
}

std::string H5Reader::ReadStringAttribute(const std::string& object_path,
                                          const std::string& key) const {
  const std::string field = object_path + "@" + key;
  if (!HasAttribute(object_path, key))
    throw Error(ErrorKind::kInput, "missing attribute", {.file = impl_->name, .field = field});
  try {
    return VisitObject(*impl_->file, object_path, [&](H5::H5Object& o) {
      return impl_->checked->ReadTextAttribute(o.openAttribute(key), field);
    });
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot read attribute: " + e.getDetailMsg(),
                {.file = impl_->name, .field = field});
  }
}

double H5Reader::ReadNumberAttribute(const std::string& object_path, const std::string& key) const {
  const std::string field = object_path + "@" + key;
  if (!HasAttribute(object_path, key))
    throw Error(ErrorKind::kInput, "missing attribute", {.file = impl_->name, .field = field});
  try {
    return VisitObject(*impl_->file, object_path, [&](H5::H5Object& o) {
      return impl_->checked->ReadNumberAttribute(o.openAttribute(key), field);
    });
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot read attribute: " + e.getDetailMsg(),
                {.file = impl_->name, .field = field});
  }
}

std::int64_t H5Reader::ReadIntegerAttribute(const std::string& object_path, const std::string& key,
                                            std::int64_t min, std::int64_t max) const {
  const double value = ReadNumberAttribute(object_path, key);
  // Compared as doubles first: casting NaN or 1e300 to an integer is undefined.
  if (!(value >= static_cast<double>(min) && value <= static_cast<double>(max)) ||
      value != std::floor(value))
    throw Error(ErrorKind::kInput, "attribute out of range",
                {.file = impl_->name, .field = object_path + "@" + key,
                 .value = fmt::format("{:g}", value),
                 .expected = fmt::format("an integer from {} to {}", min, max)});
  return static_cast<std::int64_t>(value);
}

}  // namespace bridgefit::io
