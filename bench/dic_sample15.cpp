// DIC Challenge Sample 15 (tests/data crop, x = 990..1010 of the full image):
// RMS of v against the exact staircase for subset sizes 21, 35, 51 and first-
// and second-order shape functions, i.e. how the subset smears the steps.
// command.csv gives v at the deformed row; the Lagrangian profile v_L(Y) =
// v(Y + v_L(Y)) is compared.
//   bench/dic_sample15 [data dir = tests/data/dic]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

using namespace bridgefit::dic;

int main(int argc, char** argv) {
  const std::string d =
      (argc > 1 ? std::string(argv[1]) : std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/dic") +
      "/sample15/";
  std::vector<std::vector<double>> ex;
  std::ifstream in(d + "command.csv");
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::stringstream s(line);
    std::string it;
    while (std::getline(s, it, ',')) r.push_back(std::stod(it));
    if (!r.empty()) ex.push_back(r);
  }
  const int rows = static_cast<int>(ex.size());
  auto lagrangian = [&](int col) {
    auto at = [&](double y) {
      y = std::clamp(y, 0.0, rows - 1.0);
      const int y0 = std::min(static_cast<int>(y), rows - 2);
      const double t = y - y0;
      return (1 - t) * ex[y0][col] + t * ex[y0 + 1][col];
    };
    std::vector<double> v(rows);
    for (int Y = 0; Y < rows; ++Y) {
      double x = ex[Y][col];
      for (int k = 0; k < 100; ++k) x = at(Y + x);
      v[Y] = x;
    }
    return v;
  };
  const Image ref = ReadImage(d + "Reference_cols900-1099.png");
  std::printf("%-6s %-7s %-7s %-12s %-10s %-7s\n", "image", "subset", "shape", "rms_v_px", "max_px",
              "points");
  for (auto [file, col] : {std::pair<const char*, int>{"P200_K50_N2_cols900-1099.png", 1},
                           {"P200_K400_N2_cols900-1099.png", 8}}) {
    const Image def = ReadImage(d + file);
    const std::vector<double> exact = lagrangian(col);
    for (int subset : {21, 35, 51})
      for (int order = 0; order < 2; ++order) {
        CorrelationOptions o;
        o.subset_size = subset;
        o.step = 5;
        o.roi_x0 = 90;
        o.roi_x1 = 111;
        o.shape = order ? ShapeFunction::kSecondOrder : ShapeFunction::kFirstOrder;
        const DisplacementField f = CorrelatePair(ref, def, o);
        double sum2 = 0, max_e = 0;
        size_t n = 0;
        for (size_t i = 0; i < f.size(); ++i) {
          if (!f.ok(i) || f.y[i] >= rows) continue;
          const double e = f.v[i] - exact[static_cast<int>(f.y[i])];
          sum2 += e * e;
          max_e = std::max(max_e, std::abs(e));
          ++n;
        }
        std::printf("%-6s %-7d %-7s %-12.4f %-10.3f %-7zu\n", col == 1 ? "K50" : "K400", subset,
                    order ? "second" : "first", std::sqrt(sum2 / std::max<size_t>(n, 1)), max_e, n);
      }
  }
  return 0;
}
