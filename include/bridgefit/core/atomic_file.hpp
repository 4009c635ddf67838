#pragma once
// Outputs are written to a temporary name beside the target and renamed on
// success, so a failed run never leaves a half-written file.

#include <filesystem>
#include <string>
#include <string_view>

namespace bridgefit {

class AtomicOutput {
 public:
  explicit AtomicOutput(std::filesystem::path target);
  ~AtomicOutput();  // removes the temporary file unless Commit() succeeded
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // Where to write (same folder as the target, so the rename is atomic).
  const std::filesystem::path& temporary_path() const { return temporary_; }
  const std::filesystem::path& target_path() const { return target_; }
  // Renames the temporary file onto the target. Throws Error on failure.
  void Commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  bool committed_ = false;
};

// Writes `content` to `path` atomically. Throws Error naming the path.
void WriteTextFileAtomic(const std::filesystem::path& path, std::string_view content);

}  // namespace bridgefit
