#pragma once
// Reading optional HDF5 content (src/pipeline readers): an absent attribute
// or dataset is empty / NaN, never an error.
#include <cmath>
#include <string>
#include <vector>

#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::pipeline::detail {

inline std::string StringAttr(const io::H5Reader& r, const std::string& object, const std::string& key) {
  return r.HasAttribute(object, key) ? r.ReadStringAttribute(object, key) : std::string();
}
inline double NumberAttr(const io::H5Reader& r, const std::string& object, const std::string& key) {
  return r.HasAttribute(object, key) ? r.ReadNumberAttribute(object, key) : NAN;
}
inline std::vector<double> VectorOrEmpty(const io::H5Reader& r, const std::string& path) {
  return r.Exists(path) ? r.ReadVector(path) : std::vector<double>();
}

}  // namespace bridgefit::pipeline::detail
