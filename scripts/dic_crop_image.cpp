// One-off tool that made the cropped test images in tests/data/dic (see
// tests/data/dic/PROVENANCE.md). Keeps the bit depth; lossless PNG out.
//   g++ -O2 -std=c++17 scripts/dic_crop_image.cpp -o /tmp/dic_crop $(pkg-config --cflags --libs opencv4)
//   /tmp/dic_crop IN OUT X Y W H
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: dic_crop IN OUT X Y W H\n");
    return 2;
  }
  const cv::Mat in = cv::imread(argv[1], cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (in.empty()) {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }
  const cv::Rect r(std::atoi(argv[3]), std::atoi(argv[4]), std::atoi(argv[5]), std::atoi(argv[6]));
  if ((r & cv::Rect(0, 0, in.cols, in.rows)) != r) {
    std::fprintf(stderr, "crop %dx%d+%d+%d outside %dx%d\n", r.width, r.height, r.x, r.y, in.cols,
                 in.rows);
    return 1;
  }
  if (!cv::imwrite(argv[2], in(r).clone(), {cv::IMWRITE_PNG_COMPRESSION, 9})) return 1;
  std::printf("%s: %dx%d depth %d -> %s (%dx%d+%d+%d)\n", argv[1], in.cols, in.rows,
              in.depth() == CV_16U ? 16 : 8, argv[2], r.width, r.height, r.x, r.y);
  return 0;
}
