// Image I/O through OpenCV (kept out of the public headers) and the
// expansion of command-line image arguments (folder, glob, files).
#include "bridgefit/dic/image.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cctype>
#include <cstdio>
#include <fnmatch.h>
#include <mutex>
#include <string>
#include <system_error>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"

namespace bridgefit::dic {
namespace fs = std::filesystem;
namespace {

// The codecs under OpenCV (libpng, libtiff) print their own "libpng error:"
// lines on stderr before imread returns an empty image; while decoding, the
// process's stderr goes to a temporary file so that the text can join our
// error message instead. File descriptor 2 belongs to the whole process, so
// the swap is serialised: two decodes on two threads take turns (bridgefit
// reads its images one at a time; a library user may not). Text another
// thread writes to stderr during a decode joins that decode's message.
class StderrCapture {
 public:
  StderrCapture() : lock_(Mutex()), file_(std::tmpfile()) {
    if (!file_) return;
    std::fflush(stderr);
    saved_ = dup(STDERR_FILENO);
    if (saved_ < 0 || dup2(fileno(file_), STDERR_FILENO) < 0) Restore();
  }
  ~StderrCapture() {
    Restore();
    if (file_) std::fclose(file_);
  }
  // Restores stderr and returns what was written meanwhile.
  std::string Release() {
    Restore();
    std::string text;
    if (!file_) return text;
    std::rewind(file_);
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, file_)) text += buffer;
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
  }

 private:
  void Restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    dup2(saved_, STDERR_FILENO);
    close(saved_);
    saved_ = -1;
  }
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  std::lock_guard<std::mutex> lock_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

// PNG, TIFF (classic and BigTIFF, either byte order), BMP, JPEG, PBM/PGM/PPM.
bool HasSupportedImageSignature(std::string_view b) {
  auto starts = [&b](std::string_view magic) { return b.substr(0, magic.size()) == magic; };
  using namespace std::string_view_literals;
  return starts("\x89PNG\r\n\x1a\n"sv) || starts("II*\0"sv) || starts("MM\0*"sv) ||
         starts("II+\0"sv) || starts("MM\0+"sv) || starts("BM"sv) || starts("\xff\xd8\xff"sv) ||
         (b.size() >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6');
}

}  // namespace

Image ReadImage(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw Error(ErrorKind::kInput, "image file not found", {.file = path.string()});
  // An image file bigger than its largest allowed pixel count at 8 bytes a
  // pixel is refused before it is read.
  const InputLimits limits = InputLimits::FromEnvironment();
  const std::string bytes = ReadFileLimited(path, limits.max_image_pixels * 8,
                                            InputLimits::kImagePixelsVariable, "image file");
  return DecodeImage(bytes, path.string(), limits);
}

Image DecodeImage(std::string_view bytes, const std::string& name, const InputLimits& limits) {
  // Only the formats a DIC camera writes reach a decoder (fuzzing found an
  // OpenEXR header that ended the process inside OpenCV's EXR codec).
  if (!bytes.empty() && !HasSupportedImageSignature(bytes))
    throw Error(ErrorKind::kInput, "unsupported image format (unknown file signature)",
                {.file = name,
                 .expected = "PNG, TIFF, BMP, JPEG or PGM/PPM (8- or 16-bit grayscale)"});
  cv::Mat mat;
  std::string codec_text;
  {
    StderrCapture capture;
    try {
      const cv::Mat buffer(1, static_cast<int>(std::min<std::size_t>(bytes.size(), INT32_MAX)),
                           CV_8U, const_cast<char*>(bytes.data()));
      // OpenCV checks the header's size against OPENCV_IO_MAX_IMAGE_PIXELS
      // before decoding; the CLI sets that to the limit below.
      if (!bytes.empty()) mat = cv::imdecode(buffer, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    } catch (const cv::Exception& e) {
      codec_text = capture.Release();
      throw Error(ErrorKind::kInput, std::string("cannot decode image: ") + e.what(),
                  {.file = name, .value = codec_text});
    } catch (const std::exception& e) {  // a codec's own exception (bad_alloc, ...)
      codec_text = capture.Release();
      throw Error(ErrorKind::kInput, std::string("cannot decode image: ") + e.what(),
                  {.file = name, .value = codec_text});
    }
    codec_text = capture.Release();
  }
  if (mat.empty())
    throw Error(ErrorKind::kInput, "cannot read image (corrupt, not an image, unsupported format "
                                   "or over the pixel limit)",
                {.file = name, .value = codec_text,
                 .expected = "an 8- or 16-bit grayscale image (png, tif, bmp, jpg, pgm) of at most " +
                             std::to_string(limits.max_image_pixels) + " pixels (" +
                             InputLimits::kImagePixelsVariable + ")"});
  if (!codec_text.empty()) std::fprintf(stderr, "%s: %s\n", name.c_str(), codec_text.c_str());
  CheckLimit(static_cast<std::uint64_t>(mat.total()), limits.max_image_pixels,
             InputLimits::kImagePixelsVariable, "the image", "pixels", name);
  if (mat.dims != 2)
    throw Error(ErrorKind::kInput, "not a 2-D image", {.file = name});
  if (mat.channels() == 3) cv::cvtColor(mat, mat, cv::COLOR_BGR2GRAY);
  else if (mat.channels() == 4) cv::cvtColor(mat, mat, cv::COLOR_BGRA2GRAY);
  else if (mat.channels() != 1)
    throw Error(ErrorKind::kInput, "unsupported number of channels",
                {.file = name, .value = std::to_string(mat.channels()),
                 .expected = "a grayscale (or colour) image"});
  const int depth = mat.depth();
  if (depth != CV_8U && depth != CV_16U && depth != CV_32F)
    throw Error(ErrorKind::kInput, "unsupported image depth",
                {.file = name, .expected = "8- or 16-bit grayscale"});
  Image image(mat.cols, mat.rows, 0.0f, depth == CV_8U ? 8 : 16);
  cv::Mat wrapped(mat.rows, mat.cols, CV_32F, image.pixels.data());
  mat.convertTo(wrapped, CV_32F);
  return image;
}

void WriteImage(const fs::path& path, const Image& image, int bit_depth) {
  BF_CHECK_INPUT(bit_depth == 8 || bit_depth == 16, "bit depth must be 8 or 16",
                 {.field = "bit_depth", .value = std::to_string(bit_depth)});
  cv::Mat wrapped(image.height, image.width, CV_32F,
                  const_cast<float*>(image.pixels.data()));
  cv::Mat out;
  wrapped.convertTo(out, bit_depth == 8 ? CV_8U : CV_16U);  // rounds and saturates
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), out);
  } catch (const cv::Exception& e) {
    ok = false;
  }
  if (!ok) throw Error(ErrorKind::kRuntime, "cannot write image", {.file = path.string()});
}

Image Crop(const Image& image, int x0, int y0, int w, int h) {
  BF_CHECK_INPUT(x0 >= 0 && y0 >= 0 && w > 0 && h > 0 && x0 + w <= image.width &&
                     y0 + h <= image.height,
                 "crop rectangle outside the image");
  Image out(w, h, 0.0f, image.bit_depth);
  for (int y = 0; y < h; ++y)
    std::copy_n(image.pixels.data() + static_cast<size_t>(y + y0) * image.width + x0, w,
                out.pixels.data() + static_cast<size_t>(y) * w);
  return out;
}

bool NaturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t i1 = i, j1 = j;
      while (i1 < a.size() && a[i1] == '0') ++i1;
      while (j1 < b.size() && b[j1] == '0') ++j1;
      size_t i2 = i1, j2 = j1;
      while (i2 < a.size() && std::isdigit(static_cast<unsigned char>(a[i2]))) ++i2;
      while (j2 < b.size() && std::isdigit(static_cast<unsigned char>(b[j2]))) ++j2;
      if (i2 - i1 != j2 - j1) return i2 - i1 < j2 - j1;
      const int c = a.compare(i1, i2 - i1, b, j1, j2 - j1);
      if (c != 0) return c < 0;
      if (i2 - i != j2 - j) return i2 - i < j2 - j;  // fewer leading zeros first
      i = i2;
      j = j2;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

namespace {

bool IsImageExtension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".tif" || ext == ".tiff" || ext == ".bmp" || ext == ".jpg" ||
         ext == ".jpeg" || ext == ".pgm" || ext == ".jp2";
}

void SortNatural(std::vector<fs::path>& paths) {
  std::sort(paths.begin(), paths.end(), [](const fs::path& a, const fs::path& b) {
    return NaturalLess(a.filename().string(), b.filename().string());
  });
}

}  // namespace

std::vector<fs::path> ExpandImageArguments(const std::vector<std::string>& args) {
  const InputLimits limits = InputLimits::FromEnvironment();
  std::vector<fs::path> out;
  std::error_code ec;
  for (const std::string& arg : args) {
    const fs::path p(arg);
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> files;
      for (const auto& entry : fs::directory_iterator(p, ec))
        if (entry.is_regular_file(ec) && IsImageExtension(entry.path())) files.push_back(entry.path());
      if (files.empty())
        throw Error(ErrorKind::kInput, "folder holds no image files",
                    {.file = arg, .expected = "png, tif, bmp, jpg or pgm files"});
      SortNatural(files);
      out.insert(out.end(), files.begin(), files.end());
    } else if (arg.find_first_of("*?[") != std::string::npos && !fs::exists(p, ec)) {
      const fs::path folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
      const std::string pattern = p.filename().string();
      std::vector<fs::path> files;
      if (fs::is_directory(folder, ec))
        for (const auto& entry : fs::directory_iterator(folder, ec))
          if (entry.is_regular_file(ec) &&
              fnmatch(pattern.c_str(), entry.path().filename().c_str(), 0) == 0)
            files.push_back(entry.path());
      if (files.empty())
        throw Error(ErrorKind::kInput, "no file matches the pattern", {.file = arg});
      SortNatural(files);
      out.insert(out.end(), files.begin(), files.end());
    } else {
      if (!fs::is_regular_file(p, ec))
        throw Error(ErrorKind::kInput, "image file not found", {.file = arg});
      out.push_back(p);
    }
  }
  if (out.empty())
    throw Error(ErrorKind::kInput, "no images given", {.expected = "a folder, a glob or files"});
  CheckLimit(out.size(), limits.max_frames, InputLimits::kFramesVariable, "the image sequence",
             "frames", args.empty() ? std::string() : args.front());
  return out;
}

}  // namespace bridgefit::dic
