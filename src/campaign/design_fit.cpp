// Experiment design from a fit: the fitted law's bound and region, each run
// through RunDesign over the same sizes (campaign/design_fit.hpp).
#include "bridgefit/campaign/design_fit.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/campaign/campaign.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::campaign {
namespace {

const char* SpecimenName(SpecimenType type) { return type == SpecimenType::kCT ? "ct" : "dcb"; }

// n points from lo to hi, geometric (intervals of sigma_c can span a factor
// of ten); one point when lo == hi.
std::vector<double> Spaced(double lo, double hi, int n) {
  if (!(hi > lo)) return {lo};
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1)));
  return v;
}

RegionLaw Completed(const laws::LawShape& shape, double sigma_c, double J_B) {
  laws::LawScales given;
  given.sigma_c = sigma_c;
  given.J_B = J_B;
  given.delta_c = NAN;
  const laws::LawScales s = laws::CompleteScales(shape, given);
  return {s.sigma_c, s.J_B, s.delta_c};
}

// Per size: the bound law's onset and the region's worst case.
FitDesignSize Combine(const FitDesignResult& r, std::size_t k) {
  FitDesignSize out;
  const DesignSize& b = r.bound_design.sizes[k];
  out.size = b.size;
  out.notch = b.notch;
  out.window_end = b.window_end;
  out.bound_onset = b.reached ? b.onset : NAN;
  out.bound_identifies = b.identifies;
  double worst_delta_c = -1.0;
  bool all_reached = true;
  for (std::size_t i = 0; i < r.region_designs.size(); ++i) {
    const DesignSize& d = r.region_designs[i].sizes[k];
    out.region_unknown += d.status != RunStatus::kOk;
    out.region_identify += d.identifies;
    if (d.reached) {
      ++out.region_reached;
      if (!(d.onset >= out.min_onset)) out.min_onset = d.onset;
      if (!(d.onset <= out.max_onset)) out.max_onset = d.onset;
      if (all_reached && d.onset >= out.max_onset) out.worst_law = static_cast<int>(i);
    } else if (r.region[i].delta_c > worst_delta_c) {  // not reached: worse than any onset
      all_reached = false;
      worst_delta_c = r.region[i].delta_c;
      out.worst_law = static_cast<int>(i);
    }
  }
  if (all_reached) out.worst_onset = out.max_onset;
  return out;
}

}  // namespace

pipeline::FittedLaw ReadDesignLaw(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw Error(ErrorKind::kInput, "the file does not exist",
                {.file = path.string(),
                 .expected = "a fit file (bridgefit fit --out FIT.h5) or a campaign.h5"});
  if (!pipeline::IsHdf5File(path)) return pipeline::ReadFittedLaw(path);  // throws, naming it
  const io::H5Reader reader(path);
  if (reader.Exists("/campaign")) return ReadCampaignLaw(reader, path);
  return pipeline::ReadFittedLaw(reader, path);
}

bool FitDesignRequest::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(law.sigma_c.value > 0)) return fail("the fit gives no sigma_c");
  if (!(law.J_tip_c.value > 0)) return fail("the fit gives no J_tip,c");
  if (!(law.J_B.identified ? law.J_B.value > 0 : law.J_B.lower_bound > 0))
    return fail("the fit gives neither J_B nor a lower bound of it");
  const SpecimenType own = scene ? scene->specimen.type : law.scene.specimen.type;
  if (specimen && *specimen != own)
    return fail(fmt::format(
        "--specimen {} but the {} is a {}: designing another shape needs its scene (--scene)",
        SpecimenName(*specimen), scene ? "scene given" : "fit's specimen", SpecimenName(own)));
  if (grid < 2 || grid > 9)
    return fail(fmt::format("the region grid must be 2 .. 9, got {}", grid));
  if (!(jb_cap_factor >= 1.0)) return fail("the J_B cap factor must be >= 1");
  if (!(sigma_c_span > 1.0)) return fail("the sigma_c span must be > 1");
  DesignRequest probe;
  probe.scene = law.scene;
  probe.scene.fracture = FractureSpec{law.J_tip_c.value};
  probe.scene.bridging = BridgingSpec{};
  probe.sizes = sizes;
  probe.resolution_fraction = resolution_fraction;
  probe.r_points = r_points;
  probe.points_past_onset = points_past_onset;
  return probe.IsValid(why);
}

Scene DesignScene(const FitDesignRequest& request, const RegionLaw& law) {
  Scene scene = request.scene ? *request.scene : request.law.scene;
  scene.fracture = FractureSpec{request.law.J_tip_c.value};
  BridgingSpec bridging;
  bridging.shape = request.law.shape;
  bridging.scales.sigma_c = law.sigma_c;
  bridging.scales.J_B = law.J_B;
  bridging.scales.delta_c = law.delta_c;
  scene.bridging = bridging;
  scene.run = RunSpec{};
  scene.Validate();
  return scene;
}

void ChooseLaws(const FitDesignRequest& request, FitDesignResult* result) {
  const pipeline::FittedLaw& f = request.law;
  const bool jb_bound = !f.J_B.identified;
  const double jb = jb_bound ? f.J_B.lower_bound : f.J_B.value;
  result->bound = Completed(f.shape, f.sigma_c.value, jb);
  result->bound_text = fmt::format(
      "sigma_c {:.4g} MPa (fitted), J_B {:.4g} J/m^2 ({}), delta_c {:.4g} mm, J_tip,c {:.5g} J/m^2",
      result->bound.sigma_c * 1e-6, result->bound.J_B, jb_bound ? "lower bound" : "fitted",
      result->bound.delta_c * 1e3, f.J_tip_c.value);
  // sigma_c's interval; an open or zero end (sigma_c -> 0 would need an
  // infinite specimen) is replaced by value / span or value x span, stated.
  const double v = f.sigma_c.value, span = request.sigma_c_span;
  const bool lo_ok = f.sigma_c.ci95_low > 0 && f.sigma_c.ci95_low <= v;
  const bool hi_ok = std::isfinite(f.sigma_c.ci95_high) && f.sigma_c.ci95_high >= v;
  const double s_lo = lo_ok ? f.sigma_c.ci95_low : v / span;
  const double s_hi = hi_ok ? f.sigma_c.ci95_high : v * span;
  const std::string s_text =
      lo_ok && hi_ok ? "its 95% interval"
                     : fmt::format("its 95% interval, {} end open or zero: value {} {:g} instead",
                                   lo_ok   ? "upper"
                                   : hi_ok ? "lower"
                                           : "each",
                                   lo_ok   ? "x"
                                   : hi_ok ? "/"
                                           : "/ and x",
                                   span);
  double j_lo = jb, j_hi = jb;
  std::string j_text;
  if (!jb_bound && f.J_B.ci95_low > 0 && f.J_B.ci95_high > f.J_B.ci95_low) {
    j_lo = f.J_B.ci95_low;
    j_hi = f.J_B.ci95_high;
    j_text = "its 95% interval";
  } else if (jb_bound) {
    j_hi = request.jb_cap_factor * jb;
    j_text = fmt::format(
        "lower bound up to a cap of {:g} x the bound (an assumption: the data "
        "give no upper end)",
        request.jb_cap_factor);
  } else {
    j_text = "its value (no interval)";
  }
  result->region.clear();
  for (double s : Spaced(s_lo, s_hi, request.grid))
    for (double j : Spaced(j_lo, j_hi, request.grid))
      result->region.push_back(Completed(f.shape, s, j));
  result->region_text = fmt::format(
      "sigma_c {:.4g} .. {:.4g} MPa ({}), J_B {:.4g} .. {:.4g} J/m^2 ({}); {} law(s), geometric "
      "{}x{} grid",
      s_lo * 1e-6, s_hi * 1e-6, s_text, j_lo, j_hi, j_text, result->region.size(), request.grid,
      request.grid);
}

FitDesignResult RunFitDesign(const FitDesignRequest& request) {
  std::string why;
  if (!request.IsValid(&why))
    throw Error(ErrorKind::kInput, why, {.file = request.law.source, .field = "design"});
  const auto t0 = std::chrono::steady_clock::now();
  FitDesignResult result;
  result.source = request.law.source;
  result.note = request.law.note;
  ChooseLaws(request, &result);
  const auto design = [&](const RegionLaw& law) {
    DesignRequest d;
    d.scene = DesignScene(request, law);
    d.sizes = request.sizes;
    d.resolution_fraction = request.resolution_fraction;
    d.r_points = request.r_points;
    d.points_past_onset = request.points_past_onset;
    return RunDesign(d);
  };
  result.bound_design = design(result.bound);
  result.specimen = result.bound_design.sizes.front().scene.specimen.type;
  for (const RegionLaw& law : result.region) result.region_designs.push_back(design(law));
  for (std::size_t k = 0; k < request.sizes.size(); ++k) {
    result.sizes.push_back(Combine(result, k));
    const FitDesignSize& s = result.sizes.back();
    if (result.smallest_region < 0 && s.region_identify == static_cast<int>(result.region.size()))
      result.smallest_region = static_cast<int>(k);
  }
  result.smallest_bound = result.bound_design.smallest;
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

std::string FitDesignResult::Warning() const {
  std::string w = bound_design.Warning();
  const int end = smallest_region >= 0 ? smallest_region : static_cast<int>(sizes.size());
  int unknown = 0;
  for (int i = 0; i < end; ++i) unknown += sizes[i].region_unknown;
  if (unknown > 0)
    w += fmt::format(
        "{}{} run(s) of the region's laws stopped early {}: the region's smallest "
        "size may be smaller",
        w.empty() ? "" : "; ", unknown,
        smallest_region >= 0 ? "below its smallest size" : "on the grid");
  return w;
}

std::string FitDesignResult::BriefReport() const {
  std::ostringstream out;
  const bool ct = specimen == SpecimenType::kCT;
  const char* size_name = ct ? "W" : "L";
  const auto mm = [](double v) {
    return std::isfinite(v) ? fmt::format("{:.1f}", v * 1e3) : std::string("not reached");
  };
  out << "  law: " << note << "\n  bound law: " << bound_text << "\n  region: " << region_text
      << "\n";
  out << fmt::format("  {:>8} {:>8} {:>11} {:>16} {:>19} {:>16}\n", ct ? "W [mm]" : "L [mm]",
                     "a0 [mm]", "window [mm]", "bound onset [mm]", "worst onset [mm]",
                     "region identifies");
  for (const FitDesignSize& s : sizes)
    out << fmt::format("  {:>8.1f} {:>8.1f} {:>11.1f} {:>16} {:>19} {:>16}\n", s.size * 1e3,
                       s.notch * 1e3, s.window_end * 1e3, mm(s.bound_onset), mm(s.worst_onset),
                       fmt::format("{}/{}", s.region_identify, region.size()));
  out << (smallest_bound >= 0 ? fmt::format("  smallest size identifying J_B and delta_c at the "
                                            "bound law: {} = {:.1f} mm\n",
                                            size_name, sizes[smallest_bound].size * 1e3)
                              : "  smallest size at the bound law: none in the range\n");
  out << (smallest_region >= 0
              ? fmt::format("  smallest size identifying them for every law of the region: {} = "
                            "{:.1f} mm\n",
                            size_name, sizes[smallest_region].size * 1e3)
              : "  smallest size for every law of the region: none in the range\n");
  if (const std::string w = Warning(); !w.empty()) out << "  warning: " << w << "\n";
  out << fmt::format("  {} reduced-model runs in {:.1f} s\n", sizes.size() * (1 + region.size()),
                     wall_s);
  return out.str();
}

report::DesignChartView DesignChartOf(const FitDesignResult& r) {
  report::DesignChartView v;
  const bool ct = r.specimen == SpecimenType::kCT;
  v.size_name = ct ? "W" : "L";
  v.title = fmt::format("{}: steady-state onset, {} specimens",
                        std::filesystem::path(r.source).filename().string(), ct ? "CT" : "DCB");
  for (const FitDesignSize& s : r.sizes) {
    v.size.push_back(s.size);
    v.notch.push_back(s.notch);
    v.window_end.push_back(s.window_end);
    v.bound_onset.push_back(s.bound_onset);
    const bool all = s.region_reached == static_cast<int>(r.region.size());
    v.region_low.push_back(s.region_reached > 0 ? s.min_onset : s.window_end);
    v.region_high.push_back(all ? s.max_onset : s.window_end);
  }
  if (r.smallest_bound >= 0) v.smallest_bound = r.sizes[r.smallest_bound].size;
  if (r.smallest_region >= 0) v.smallest_region = r.sizes[r.smallest_region].size;
  return v;
}

}  // namespace bridgefit::campaign
