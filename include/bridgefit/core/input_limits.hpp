#pragma once
// Size limits on everything bridgefit reads, checked before memory is
// committed. Every file can come from someone else's machine; a limit hit is
// an Error naming the limit and the environment variable that raises it.
//
//   BRIDGEFIT_MAX_TEXT_BYTES        CSV records, scene files       512 MiB
//   BRIDGEFIT_MAX_TABLE_BYTES       bridging-law table files         16 MiB
//   BRIDGEFIT_MAX_CSV_ROWS          data rows in one CSV         20,000,000
//   BRIDGEFIT_MAX_CSV_COLUMNS       columns in one CSV                1,000
//   BRIDGEFIT_MAX_LINE_BYTES        one CSV line                      1 MiB
//   BRIDGEFIT_MAX_IMAGE_PIXELS      pixels in one image         268,435,456
//   BRIDGEFIT_MAX_FRAMES            images in one DIC sequence      100,000
//   BRIDGEFIT_MAX_DATASET_ELEMENTS  elements in one HDF5 dataset 268,435,456

#include <cstdint>
#include <filesystem>
#include <string>

namespace bridgefit {

struct InputLimits {
  std::uint64_t max_text_bytes = std::uint64_t{512} << 20;
  std::uint64_t max_table_bytes = std::uint64_t{16} << 20;
  std::uint64_t max_csv_rows = 20'000'000;
  std::uint64_t max_csv_columns = 1'000;
  std::uint64_t max_line_bytes = std::uint64_t{1} << 20;
  std::uint64_t max_image_pixels = std::uint64_t{1} << 28;
  std::uint64_t max_frames = 100'000;
  std::uint64_t max_dataset_elements = std::uint64_t{1} << 28;

  static constexpr const char* kTextBytesVariable = "BRIDGEFIT_MAX_TEXT_BYTES";
  static constexpr const char* kTableBytesVariable = "BRIDGEFIT_MAX_TABLE_BYTES";
  static constexpr const char* kCsvRowsVariable = "BRIDGEFIT_MAX_CSV_ROWS";
  static constexpr const char* kCsvColumnsVariable = "BRIDGEFIT_MAX_CSV_COLUMNS";
  static constexpr const char* kLineBytesVariable = "BRIDGEFIT_MAX_LINE_BYTES";
  static constexpr const char* kImagePixelsVariable = "BRIDGEFIT_MAX_IMAGE_PIXELS";
  static constexpr const char* kFramesVariable = "BRIDGEFIT_MAX_FRAMES";
  static constexpr const char* kDatasetElementsVariable = "BRIDGEFIT_MAX_DATASET_ELEMENTS";

  // The defaults above, each replaced by its environment variable when that
  // is set (a positive integer; anything else is an Error naming it).
  static InputLimits FromEnvironment();
};

// Throws Error(kInput) "<what> has N <unit>, over the limit of M (VARIABLE)"
// with the way to raise it, when count > limit.
void CheckLimit(std::uint64_t count, std::uint64_t limit, const char* variable,
                const std::string& what, const std::string& unit, const std::string& file);

// Reads a whole file, never more than `max_bytes` (+1 to detect the excess):
// /dev/zero or a huge file is refused at the limit instead of exhausting memory.
std::string ReadFileLimited(const std::filesystem::path& path, std::uint64_t max_bytes,
                            const char* variable, const std::string& what);

}  // namespace bridgefit
