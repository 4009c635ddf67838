#include "bridgefit/io/hdf5.hpp"

#include <H5Cpp.h>

#include <ctime>
#include <optional>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/version.hpp"

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

void H5Writer::Commit() {
  try {
    impl_->file->close();
  } catch (const H5::Exception& e) {
    Fail(impl_->target.string(), "could not close HDF5 file", e);
  }
  impl_->output->Commit();
}

// ---- Reader ---------------------------------------------------------------

struct H5Reader::Impl {
  std::string name;
  std::unique_ptr<H5::H5File> file;
};

H5Reader::H5Reader(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
  impl_->name = path.string();
  if (!std::filesystem::exists(path))
    throw Error(ErrorKind::kInput, "file not found", {.file = impl_->name});
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
    H5::DataSet dataset = impl_->file->openDataSet(path);
    const H5::DataSpace space = dataset.getSpace();
    const hssize_t n = space.getSimpleExtentNpoints();
    std::vector<double> values(static_cast<size_t>(n));
    if (n > 0) dataset.read(values.data(), H5::PredType::NATIVE_DOUBLE);
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
    H5::DataSet dataset = impl_->file->openDataSet(path);
    const hssize_t n = dataset.getSpace().getSimpleExtentNpoints();
    std::vector<char*> pointers(static_cast<size_t>(n), nullptr);
    const H5::StrType type = VariableString();
    if (n > 0) dataset.read(pointers.data(), type);
    std::vector<std::string> out;
    for (char* p : pointers) {
      out.emplace_back(p ? p : "");
      std::free(p);
    }
    return out;
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
  if (!HasAttribute(object_path, key))
    throw Error(ErrorKind::kInput, "missing attribute",
                {.file = impl_->name, .field = object_path + "@" + key});
  try {
    return VisitObject(*impl_->file, object_path, [&](H5::H5Object& o) {
      H5::Attribute attribute = o.openAttribute(key);
      std::string value;
      attribute.read(attribute.getStrType(), value);
      return value;
    });
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot read attribute: " + e.getDetailMsg(),
                {.file = impl_->name, .field = object_path + "@" + key});
  }
}

double H5Reader::ReadNumberAttribute(const std::string& object_path, const std::string& key) const {
  if (!HasAttribute(object_path, key))
    throw Error(ErrorKind::kInput, "missing attribute",
                {.file = impl_->name, .field = object_path + "@" + key});
  try {
    return VisitObject(*impl_->file, object_path, [&](H5::H5Object& o) {
      H5::Attribute attribute = o.openAttribute(key);
      double value = 0.0;
      attribute.read(H5::PredType::NATIVE_DOUBLE, &value);
      return value;
    });
  } catch (const H5::Exception& e) {
    throw Error(ErrorKind::kInput, "cannot read attribute: " + e.getDetailMsg(),
                {.file = impl_->name, .field = object_path + "@" + key});
  }
}

}  // namespace bridgefit::io
