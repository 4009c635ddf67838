#pragma once
// Reads an HDF5 file as every kind of input `fit`, `report` and `rcurve`
// accept, through the library readers (the fuzz harness and the regression
// replay share it). Throws bridgefit::Error for a refused file.

#include <filesystem>

namespace bridgefit::fuzz {

// `in_child_first`: run io::CheckH5FileInChildProcess first, as the CLI does.
// Returns how many of the input kinds read without an Error.
int ReadAsEveryH5Input(const std::filesystem::path& path, bool in_child_first);

}  // namespace bridgefit::fuzz
