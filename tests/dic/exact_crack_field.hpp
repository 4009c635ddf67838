#pragma once
// An exact crack field shared by the path, flag and origin tests: an
// opening jump across the path y = path_y(x), falling as sqrt(200 - x) to
// zero at the tip x = 200, open from x = x_open on (the notch on the left),
// on a 2 px grid over x 0..240, y 0..200; u = 0.1, v = 0.05 +- the half
// opening.

#include <cmath>
#include <functional>
#include <limits>

#include "bridgefit/dic/correlation.hpp"

namespace bridgefit::dic::test_fields {

inline DisplacementField ExactOpeningField(const std::function<double(double)>& path_y,
                                           double x_open = -std::numeric_limits<double>::infinity()) {
  DisplacementField f;
  for (int y = 0; y <= 200; y += 2)
    for (int x = 0; x <= 240; x += 2) {
      const double side = y > path_y(x) ? 1.0 : -1.0;
      const bool open = x >= x_open && x < 200;
      f.x.push_back(x);
      f.y.push_back(y);
      f.u.push_back(0.1);
      f.v.push_back(0.05 + (open ? 0.5 * side * std::sqrt((200.0 - x) / 200.0) : 0.0));
      f.zncc.push_back(1);
      f.iterations.push_back(0);
      f.status.push_back(PointStatus::kOk);
    }
  f.nx = 121;
  f.ny = 101;
  return f;
}

}  // namespace bridgefit::dic::test_fields
