#include "bridgefit/core/atomic_file.hpp"

#include <fstream>
#include <random>
#include <unistd.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/interrupt.hpp"

namespace bridgefit {

AtomicOutput::AtomicOutput(std::filesystem::path target) : target_(std::move(target)) {
  const std::filesystem::path parent =
      target_.parent_path().empty() ? std::filesystem::path(".") : target_.parent_path();
  if (!std::filesystem::is_directory(parent))
    throw Error(ErrorKind::kInput, "output folder does not exist",
                {.file = target_.string(), .expected = "an existing folder for the output"});
  temporary_ = parent / ("." + target_.filename().string() + ".tmp-" +
                         std::to_string(::getpid()) + "-" +
                         std::to_string(std::random_device{}() % 1000000));
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicOutput::Commit() {
  // An interrupted run writes nothing: the temporary goes with the destructor.
  ThrowIfInterrupted("writing " + target_.string());
  std::error_code ec;
  std::filesystem::rename(temporary_, target_, ec);
  if (ec)
    throw Error(ErrorKind::kRuntime, "could not write output: " + ec.message(),
                {.file = target_.string()});
  committed_ = true;
}

void WriteTextFileAtomic(const std::filesystem::path& path, std::string_view content) {
  AtomicOutput output(path);
  {
    std::ofstream stream(output.temporary_path(), std::ios::binary);
    stream.write(content.data(), static_cast<std::streamsize>(content.size()));
    stream.close();
    if (!stream)
      throw Error(ErrorKind::kRuntime, "could not write output file", {.file = path.string()});
  }
  output.Commit();
}

}  // namespace bridgefit
