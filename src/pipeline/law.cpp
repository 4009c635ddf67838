// The law table (pipeline/law.hpp): evaluation, text and CSV.
#include "bridgefit/pipeline/law.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::pipeline {

bool LawRequest::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!std::isfinite(scales.sigma_c) || !std::isfinite(scales.delta_c))
    return fail("the law's sigma_c and delta_c must be given (laws::CompleteScales)");
  if (!(J_tip_c > 0.0)) return fail("J_tip,c must be positive");
  if (points < 2) return fail("the table needs at least 2 points");
  return true;
}

LawRun RunLaw(const LawRequest& request) {
  std::string why;
  if (!request.IsValid(&why)) throw Error(ErrorKind::kUsage, why);
  LawRun run;
  run.shape = request.shape;
  run.scales = request.scales;
  run.J_tip_c = request.J_tip_c;
  const laws::BridgingLaw law{&run.shape, run.scales.sigma_c, run.scales.delta_c};
  const int n = request.points;
  run.points.reserve(n);
  for (int i = 0; i < n; ++i) {
    const double delta = run.scales.delta_c * i / (n - 1);
    run.points.push_back({delta, law.Traction(delta), laws::ElasticZoneR(law, delta, run.J_tip_c),
                          laws::FarFieldJ(law, delta, run.J_tip_c)});
  }
  return run;
}

std::string LawRun::BriefReport() const {
  std::string text = fmt::format(
      "law {}: sigma_c = {:.6g} MPa, delta_c = {:.6g} mm, J_B = {:.6g} J/m^2, "
      "J_tip,c = {:.6g} J/m^2, steady-state R = {:.6g} J/m^2\n",
      laws::LawFamilyName(shape.family), scales.sigma_c / 1e6, scales.delta_c * 1e3, scales.J_B,
      J_tip_c, J_tip_c + scales.J_B);
  text += fmt::format("{:>14} {:>14} {:>14} {:>14}\n", "delta [mm]", "sigma [MPa]", "R [J/m^2]",
                      "J_ff [J/m^2]");
  const int n = static_cast<int>(points.size());
  const int stride = std::max(1, n / 20);
  for (int i = 0; i < n; ++i) {
    if (i % stride != 0 && i != n - 1) continue;
    const LawPoint& p = points[i];
    text += fmt::format("{:14.6g} {:14.6g} {:14.6g} {:14.6g}\n", p.delta * 1e3, p.sigma / 1e6, p.R,
                        p.J_ff);
  }
  return text;
}

void WriteLawCsv(const std::string& path, const LawRun& run) {
  std::string text = "delta [m], sigma [Pa], R [J/m^2], J_ff [J/m^2]\n";
  for (const LawPoint& p : run.points)
    text += fmt::format("{:.10g}, {:.10g}, {:.10g}, {:.10g}\n", p.delta, p.sigma, p.R, p.J_ff);
  WriteTextFileAtomic(path, text);
}

}  // namespace bridgefit::pipeline
