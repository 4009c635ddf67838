#pragma once
// Grayscale images as plain float arrays (no OpenCV types in the API).
// Pixel (x, y) is column x, row y; intensities keep the file's gray levels
// (0..255 for 8-bit, 0..65535 for 16-bit).

#include <filesystem>
#include <string_view>

#include "bridgefit/core/input_limits.hpp"
#include <string>
#include <vector>

namespace bridgefit::dic {

struct Image {
  int width = 0;
  int height = 0;
  int bit_depth = 8;          // of the source file (8 or 16)
  std::vector<float> pixels;  // row-major, width * height

  Image() = default;
  Image(int w, int h, float value = 0.0f, int depth = 8)
      : width(w), height(h), bit_depth(depth), pixels(static_cast<size_t>(w) * h, value) {}
  bool empty() const { return pixels.empty(); }
  float& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  float at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};

// Reads an 8- or 16-bit grayscale image (colour is converted to gray).
// Throws Error(kInput) naming the file when it cannot be read.
Image ReadImage(const std::filesystem::path& path);
// Decodes an image held in memory (`name` labels errors). Refuses more than
// limits.max_image_pixels pixels (BRIDGEFIT_MAX_IMAGE_PIXELS).
Image DecodeImage(std::string_view bytes, const std::string& name, const InputLimits& limits);
// Writes an image rounded and clipped to `bit_depth` (8 or 16) gray levels.
void WriteImage(const std::filesystem::path& path, const Image& image, int bit_depth);
// Copy of the rectangle [x0, x0+w) x [y0, y0+h).
Image Crop(const Image& image, int x0, int y0, int w, int h);

// "img2" < "img10": digits compare by value, the rest character by character.
bool NaturalLess(const std::string& a, const std::string& b);

// Expands command-line image arguments: a folder (its image files), a glob
// with * and ? in the file name part, or plain files. Sorted naturally, file
// names may contain spaces. Throws Error(kInput) when nothing matches.
std::vector<std::filesystem::path> ExpandImageArguments(const std::vector<std::string>& args);

}  // namespace bridgefit::dic
