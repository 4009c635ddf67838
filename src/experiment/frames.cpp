// Crack lengths measured on images put into a record (rcurve.hpp,
// CrackLengthFromFrames).
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::experiment {

ExperimentRecord CrackLengthFromFrames(const ExperimentRecord& record,
                                       const std::vector<std::string>& frame_images,
                                       const std::vector<double>& frame_crack_lengths,
                                       const std::string& source, std::vector<std::string>* notes) {
  BF_CHECK_INPUT(frame_images.size() == frame_crack_lengths.size(),
                 "image names and crack lengths differ in length", {.file = source});
  BF_CHECK_INPUT(!record.images.empty(), "the record names no images, so frames cannot be matched",
                 {.file = record.source, .field = "image",
                  .expected = "a column 'image' with the file of the frame taken at that row"});
  auto name_of = [](const std::string& path) {
    return std::filesystem::path(path).filename().string();
  };
  std::map<std::string, double> measured;
  for (std::size_t f = 0; f < frame_images.size(); ++f)
    if (std::isfinite(frame_crack_lengths[f])) measured[name_of(frame_images[f])] = frame_crack_lengths[f];
  // The matched rows in record order, with the axis they are interpolated on.
  const bool timed = !record.time.empty();
  std::vector<std::size_t> rows;
  std::vector<double> values;
  for (std::size_t r = 0; r < record.size(); ++r) {
    if (record.images[r].empty()) continue;
    const auto it = measured.find(name_of(record.images[r]));
    if (it == measured.end()) continue;
    rows.push_back(r);
    values.push_back(it->second);
  }
  BF_CHECK_INPUT(rows.size() >= 2, "fewer than two frames with a crack length match the record's images",
                 {.file = source, .field = "image",
                  .value = std::to_string(rows.size()) + " matched",
                  .expected = "the record's image names (file names, folders ignored)"});
  auto axis = [&](std::size_t r) { return timed ? record.time[r] : static_cast<double>(r); };
  ExperimentRecord out = record;
  const std::size_t last = rows.back();
  out.load.resize(last + 1);
  out.displacement.resize(last + 1);
  if (timed) out.time.resize(last + 1);
  out.images.resize(last + 1);
  out.crack_length.assign(last + 1, values.front());
  std::size_t k = 0;
  for (std::size_t r = rows.front(); r <= last; ++r) {
    while (k + 1 < rows.size() && rows[k + 1] < r) ++k;
    if (r == rows[k] || k + 1 >= rows.size()) {
      out.crack_length[r] = values[k];
      continue;
    }
    const double t0 = axis(rows[k]), t1 = axis(rows[k + 1]);
    const double w = t1 > t0 ? (axis(r) - t0) / (t1 - t0) : 0.0;
    out.crack_length[r] = values[k] + w * (values[k + 1] - values[k]);
  }
  out.metadata["crack_length"] = "from images: " + source;
  if (notes) {
    notes->push_back(fmt::format(
        "crack length from {} frames of {} (rows {}-{}), linear in {} between them; {} rows "
        "before the first take its {:.4g} mm",
        rows.size(), source, rows.front() + 1, last + 1, timed ? "time" : "row",
        rows.front(), values.front() * 1e3));
    if (last + 1 < record.size())
      notes->push_back(fmt::format("{} rows after the last frame (row {}) removed: no crack length",
                                   record.size() - last - 1, last + 1));
  }
  out.Validate();
  return out;
}

}  // namespace bridgefit::experiment
