#pragma once
// Private: shared by the crack-tip stages (crack.cpp) and the Williams fit
// (crack_williams.cpp).

#include <cstddef>
#include <vector>

#include "bridgefit/dic/crack.hpp"

namespace bridgefit::dic::detail {

struct LocalPoint {
  double s, n;       // along / normal to the line, px
  double us, un;     // displacement components along / normal, px
  double x, y;       // image position
  double u, v;       // displacement, image axes
  std::size_t index; // in the field
};

inline void SetPosition(const CrackLine& line, TipEstimate* tip) {
  line.FromLocal(tip->s_px, 0.0, &tip->x_px, &tip->y_px);
}

// Williams tip (fills res.williams and the williams_* members) from the
// continuum about the window's centre (the sqrt tip clamped to the jump tip).
void WilliamsTip(const DisplacementField& field, const std::vector<LocalPoint>& pts,
                 const CrackTipOptions& o, CrackTipResult& res);

}  // namespace bridgefit::dic::detail
