#pragma once
// R-curve theory of an elastic bridging zone, PHYSICS.md sections 3, 4, 7.

#include "bridgefit/laws/law.hpp"

namespace bridgefit::laws {

// R = J_tip,c + W(delta_root) - 1/2 sigma(delta_root) delta_root while the
// zone develops; J_tip,c + J_B once delta_root >= delta_c.  [J/m^2]
template <class T>
T ElasticZoneR(const LawT<T>& law, const T& delta_root, const T& J_tip_c) {
  if (delta_root >= law.delta_c) return J_tip_c + law.BridgingToughness();
  return J_tip_c + law.Work(delta_root) - law.Recoverable(delta_root);
}

// Far-field J: J_ff = J_tip + W(delta_root).  [J/m^2]
template <class T>
T FarFieldJ(const LawT<T>& law, const T& delta_root, const T& J_tip) {
  return J_tip + law.Work(delta_root);
}

// J_tip from a contour J that crosses the crack faces inside the bridging
// zone where the COD is delta_crossing: J_tip = J(x) - W(delta(x)).
template <class T>
T TipJFromContourInside(const LawT<T>& law, const T& J_contour, const T& delta_crossing) {
  return J_contour - law.Work(delta_crossing);
}

// J_tip from a contour that encloses the whole zone: J_tip = J - W(delta_root).
template <class T>
T TipJFromContourEnclosing(const LawT<T>& law, const T& J_contour, const T& delta_root) {
  return J_contour - law.Work(delta_root);
}

// Lower bounds when the test stopped before steady state (section 7).
struct TruncationBounds {
  double J_B_lower = 0.0;      // R_max - J_tip,c  [J/m^2]
  double delta_c_lower = 0.0;  // delta_root at the last valid point [m]
  double R_max = 0.0;          // evidence: R at the last valid point [J/m^2]
  double J_tip_c = 0.0;        // evidence [J/m^2]
  double crack_length_max = 0.0;  // evidence: a at the last valid point [m]
};

// J_B >= R_max - J_tip,c and delta_c >= delta_root,max. Throws Error for
// non-finite or negative inputs.
TruncationBounds BoundsFromTruncatedCurve(double R_max, double J_tip_c, double delta_root_max,
                                          double crack_length_max);

}  // namespace bridgefit::laws
