#pragma once
// HDF5 files in one documented layout (docs/FORMATS.md). Every dataset has
// a `units` attribute. Files are written under a temporary name and renamed
// by Commit(), so a failed run leaves no half-written file.
// The HDF5 C++ API stays inside src/io (pimpl).

#include <filesystem>
#include <functional>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"

namespace bridgefit::io {

class H5Writer {
 public:
  explicit H5Writer(const std::filesystem::path& target);
  ~H5Writer();
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  // Paths like "/rcurve/R"; parent groups are created as needed.
  void WriteVector(const std::string& path, const std::vector<double>& values,
                   const std::string& units, const std::string& description = "");
  // Row-major matrix rows x cols.
  void WriteMatrix(const std::string& path, std::size_t rows, std::size_t cols,
                   const std::vector<double>& values, const std::string& units,
                   const std::string& description = "");
  void WriteStrings(const std::string& path, const std::vector<std::string>& values);
  // Attributes on a group or dataset (created as a group if missing).
  void WriteAttribute(const std::string& object_path, const std::string& key,
                      const std::string& value);
  void WriteAttribute(const std::string& object_path, const std::string& key, double value);
  // Copies every top-level group and dataset of the HDF5 file `source`
  // (one this program wrote) under `dest_group`, with their attributes:
  // a file's layout kept inside a bigger one (campaign.h5's specimens).
  void CopyFileInto(const std::filesystem::path& source, const std::string& dest_group);
  // Closes the file and renames it onto the target.
  void Commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class H5Reader {
 public:
  explicit H5Reader(const std::filesystem::path& path);
  ~H5Reader();
  H5Reader(const H5Reader&) = delete;
  H5Reader& operator=(const H5Reader&) = delete;

  bool Exists(const std::string& path) const;
  std::vector<double> ReadVector(const std::string& path, std::string* units = nullptr) const;
  std::vector<std::string> ReadStrings(const std::string& path) const;
  std::string ReadStringAttribute(const std::string& object_path, const std::string& key) const;
  double ReadNumberAttribute(const std::string& object_path, const std::string& key) const;
  // A numeric attribute that must be an integer in [min, max]: NaN, 1e300 or
  // 2.5 are an Error naming the attribute and value, never a cast.
  std::int64_t ReadIntegerAttribute(const std::string& object_path, const std::string& key,
                                    std::int64_t min, std::int64_t max) const;
  bool HasAttribute(const std::string& object_path, const std::string& key) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Defence against crashes inside libhdf5 itself (fuzzing found several in
// 1.10.8): opens `path` in a child process and reads every dataset and
// attribute there through the same checks H5Reader uses, with the address
// space bounded. A child that dies by a signal, takes longer than
// `timeout_s`, or refuses the file makes this throw Error(kInput)
// "corrupt HDF5 file: <path> ..." (with the child's reason when it has one).
// Cost: one fork plus one extra read of the file (docs/HOSTILE_INPUT.md).
// `also_read`, when given, runs in the child after the walk: the caller's
// own reader of the file (e.g. matio's for an Ncorr MAT v7.3 file, whose
// attribute reads take libhdf5 paths the walk does not), so a crash there
// too ends only the child; an Error it throws is the child's refusal. A file
// that is not HDF5 gets `also_read` alone, with the same bounds ("corrupt
// file: ..."): e.g. a MAT v5 file, whose header can make matio allocate
// gigabytes (fuzz_ncorr).
void CheckH5FileInChildProcess(const std::filesystem::path& path, double timeout_s = 60.0,
                               const std::function<void()>& also_read = {});

// True when the file starts with the HDF5 signature (at byte 0, 512, 1024,
// ...), read without libhdf5.
bool HasHdf5Signature(const std::filesystem::path& path);

// Record types <-> HDF5 groups ("/experiment", "/rcurve", "/simulation").
void WriteRecordH5(H5Writer& file, const ExperimentRecord& record,
                   const std::string& group = "/experiment");
void WriteRecordH5(H5Writer& file, const RCurve& curve, const std::string& group = "/rcurve");
void WriteRecordH5(H5Writer& file, const SimulationResult& result,
                   const std::string& group = "/simulation");
ExperimentRecord ReadExperimentH5(const H5Reader& file, const std::string& group = "/experiment");
RCurve ReadRCurveH5(const H5Reader& file, const std::string& group = "/rcurve");
SimulationResult ReadSimulationH5(const H5Reader& file, const std::string& group = "/simulation");

}  // namespace bridgefit::io
