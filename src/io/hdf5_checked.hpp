#pragma once
// Checked reads of HDF5 datasets and attributes (private to src/io): type
// class, element count and extent-versus-file-size are checked before any
// buffer is sized from what the file claims. Shared by H5Reader and by the
// child-process check of files given on the command line.

#include <H5Cpp.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"

namespace bridgefit::io {

class H5Checked {
 public:
  H5Checked(std::string file_name, std::uint64_t file_bytes, InputLimits limits);

  // Numeric (integer or float) dataset of any rank, converted to double.
  std::vector<double> ReadNumbers(const H5::DataSet& dataset, const std::string& field) const;
  // Fixed- or variable-length string dataset.
  std::vector<std::string> ReadTexts(const H5::DataSet& dataset, const std::string& field) const;
  // Scalar (one-element) string or numeric attribute.
  std::string ReadTextAttribute(const H5::Attribute& attribute, const std::string& field) const;
  double ReadNumberAttribute(const H5::Attribute& attribute, const std::string& field) const;

  // Number of elements, refused when over the limit, when the file is too
  // small to hold them, or when the data lives in other files.
  std::uint64_t CheckedExtent(const H5::DataSet& dataset, const std::string& field,
                              std::uint64_t stored_element_bytes) const;

 private:
  void CheckScalarAttribute(const H5::Attribute& attribute, const std::string& field) const;
  Error Refuse(const std::string& field, const std::string& what, const std::string& value = "",
               const std::string& expected = "") const;

  std::string file_;
  std::uint64_t file_bytes_;
  InputLimits limits_;
};

}  // namespace bridgefit::io
