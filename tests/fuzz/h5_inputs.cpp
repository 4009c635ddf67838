#include "h5_inputs.hpp"

#include <string>
#include <vector>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::fuzz {
namespace {

// The /fit layout `bridgefit report` reads (report.cpp ReadFit) and the
// /rcurve extras `bridgefit fit` reads from an rcurve.h5.
const char* const kFitStrings[] = {"model", "optimizer", "law", "verdict", "r_kind",
                                   "scene", "stop_reason", "fit_to"};
const char* const kFitNumbers[] = {"converged", "steady_state_reached", "bridging_detected",
                                   "rms_residual_J_per_m2", "rms_residual_N", "wall_s",
                                   "evaluations"};
const char* const kFitVectors[] = {"/fit/crack_length", "/fit/R", "/fit/fitted_crack_length",
                                   "/fit/fitted_R", "/fit/load_displacement/displacement",
                                   "/fit/load_displacement/load", "/rcurve/crack_growth",
                                   "/rcurve/record_row", "/rcurve/dropped_counts"};
const char* const kStringVectors[] = {"/rcurve/dropped_reasons", "/rcurve/notes",
                                      "/experiment/images"};

template <class F>
bool Try(F&& read) {
  try {
    read();
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

int ReadAsEveryH5Input(const std::filesystem::path& path, bool in_child_first) {
  if (in_child_first) io::CheckH5FileInChildProcess(path, 20.0);
  const io::H5Reader reader(path);
  int read = 0;
  read += Try([&] { (void)io::ReadExperimentH5(reader); });
  read += Try([&] { (void)io::ReadRCurveH5(reader); });
  read += Try([&] { (void)io::ReadSimulationH5(reader); });
  read += Try([&] {
    for (const char* key : kFitStrings)
      if (reader.HasAttribute("/fit", key)) (void)reader.ReadStringAttribute("/fit", key);
    for (const char* key : kFitNumbers)
      if (reader.HasAttribute("/fit", key)) (void)reader.ReadNumberAttribute("/fit", key);
    if (reader.HasAttribute("/rcurve/figures", "initial_compliance_m_per_N"))
      (void)reader.ReadNumberAttribute("/rcurve/figures", "initial_compliance_m_per_N");
  });
  for (const char* vector : kFitVectors)
    read += Try([&] {
      std::string units;
      if (reader.Exists(vector)) (void)reader.ReadVector(vector, &units);
    });
  for (const char* strings : kStringVectors)
    read += Try([&] {
      if (reader.Exists(strings)) (void)reader.ReadStrings(strings);
    });
  return read;
}

}  // namespace bridgefit::fuzz
