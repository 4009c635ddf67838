#include "bridgefit/core/input_limits.hpp"

#include <cstdlib>
#include <fstream>

#include "bridgefit/core/error.hpp"

namespace bridgefit {
namespace {

void Override(const char* variable, std::uint64_t& limit) {
  const char* text = std::getenv(variable);
  if (!text || !*text) return;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (*end != '\0' || value == 0 || text[0] == '-')
    throw Error(ErrorKind::kUsage, "invalid size limit in the environment",
                {.field = variable, .value = text, .expected = "a positive integer"});
  limit = value;
}

}  // namespace

InputLimits InputLimits::FromEnvironment() {
  InputLimits limits;
  Override(kTextBytesVariable, limits.max_text_bytes);
  Override(kTableBytesVariable, limits.max_table_bytes);
  Override(kCsvRowsVariable, limits.max_csv_rows);
  Override(kCsvColumnsVariable, limits.max_csv_columns);
  Override(kLineBytesVariable, limits.max_line_bytes);
  Override(kImagePixelsVariable, limits.max_image_pixels);
  Override(kFramesVariable, limits.max_frames);
  Override(kDatasetElementsVariable, limits.max_dataset_elements);
  return limits;
}

void CheckLimit(std::uint64_t count, std::uint64_t limit, const char* variable,
                const std::string& what, const std::string& unit, const std::string& file) {
  if (count <= limit) return;
  throw Error(ErrorKind::kInput,
              what + " has " + (count == limit + 1 ? "more than " + std::to_string(limit)
                                                    : std::to_string(count)) +
                  " " + unit + ", over the limit of " + std::to_string(limit) + " (" + variable +
                  ")",
              {.file = file,
               .expected = std::string("at most ") + std::to_string(limit) + " " + unit +
                           "; to read a bigger input, set " + variable + "=N in the environment"});
}

std::string ReadFileLimited(const std::filesystem::path& path, std::uint64_t max_bytes,
                            const char* variable, const std::string& what) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream)
    throw Error(ErrorKind::kInput, "cannot open file",
                {.file = path.string(), .expected = "a readable " + what});
  std::string content;
  char chunk[1 << 16];
  while (stream) {
    stream.read(chunk, sizeof chunk);
    content.append(chunk, static_cast<std::size_t>(stream.gcount()));
    // Counted as limit + 1: "more than <limit>" (a device may never end).
    if (content.size() > max_bytes)
      CheckLimit(max_bytes + 1, max_bytes, variable, "the " + what, "bytes", path.string());
  }
  if (stream.bad())
    throw Error(ErrorKind::kInput, "read error", {.file = path.string()});
  return content;
}

}  // namespace bridgefit
