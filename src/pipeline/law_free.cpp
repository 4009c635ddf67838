// `bridgefit lawfree` as a call (pipeline/law_free.hpp, issue 21).
#include "bridgefit/pipeline/law_free.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"
#include "bridgefit/specimen/calibrations.hpp"

namespace bridgefit::pipeline {

dic::FrameJOptions FrameJOptionsFromScene(const Scene& scene) {
  dic::FrameJOptions o;
  o.enabled = true;
  const MaterialSpec& m = scene.material;
  const bool strain = scene.specimen.plane == PlaneCondition::kPlaneStrain;
  if (m.orthotropic) {
    if (strain)
      throw Error(ErrorKind::kInput,
                  "the DIC J integral is plane stress; an orthotropic plane-strain scene has no "
                  "plane-stress equivalent here",
                  {.file = scene.source, .field = "specimen.plane", .value = "plane_strain",
                   .expected = "plane_stress for an orthotropic material"});
    o.elastic = dic::ElasticConstants::Orthotropic(m.E1, m.E2, m.G12, m.nu12);
  } else if (strain) {
    o.elastic = dic::ElasticConstants::Isotropic(m.E / (1 - m.nu * m.nu), m.nu / (1 - m.nu));
  } else {
    o.elastic = dic::ElasticConstants::Isotropic(m.E, m.nu);
  }
  o.notch_length_m = scene.specimen.notch;
  try {
    o.elastic.Validate();
    o.effective_modulus = specimen::EffectiveModulus(m, scene.specimen.plane);
  } catch (const Error& e) {
    throw e.WithContext({.file = scene.source});
  }
  return o;
}

void TipMaterialFromScene(const Scene& scene, dic::CrackTipOptions* tip) {
  const MaterialSpec& m = scene.material;
  try {
    if (m.orthotropic) {
      const specimen::InPlaneCompliance b =
          specimen::OrthotropicInPlaneCompliance(m, scene.specimen.plane);
      tip->s11 = b.b11;
      tip->s22 = b.b22;
      tip->s12 = b.b12;
      tip->s66 = b.b66;
      return;
    }
  } catch (const Error& e) {
    throw e.WithContext({.file = scene.source});
  }
  tip->kappa = specimen::KolosovConstant(m, scene.specimen.plane);
}

bool LawFreeRequest::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (dic_file.empty()) return fail("a DIC file (dic.h5 with the J integral) is needed");
  if (!far_field_route && rcurve_file.empty())
    return fail("no route: the J_ff route is off and no R curve is given");
  if (!(j_relative_floor > 0) || !(r_relative_floor > 0) || !(j_fit_relative_floor > 0))
    return fail("the relative uncertainty floors must be > 0");
  if (J_tip_c && !(std::isfinite(*J_tip_c) && *J_tip_c >= 0))
    return fail("J_tip_c must be finite and >= 0");
  return options.IsValid(why);
}

namespace {

// |delta*| <= this many standard uncertainties reads as zero opening.
constexpr double kOnsetOpeningZ = 2.0;

bool ZeroOpening(const DicJSeries& s, size_t k) {
  if (s.delta_star_status[k] != "ok" || !std::isfinite(s.delta_star[k])) return false;
  const double u = std::isfinite(s.delta_star_uncertainty[k]) ? s.delta_star_uncertainty[k] : 0;
  return std::abs(s.delta_star[k]) <= kOnsetOpeningZ * u;
}

// The onset frame (docs/LAW_FREE.md "What each route needs"): the last
// frame of the leading run whose notch-root opening is zero within its
// uncertainty (|delta*| <= kOnsetOpeningZ u; dic writes delta* = 0 while
// the tip is at or behind the root, and the near-tip opening with the
// tip's uncertainty while it is past the root by less than the profile's
// stretch: dic/frame_j.hpp).
// The run ends at the first frame with an opening; a zero read after it is
// an anomaly (ZeroAfterGrowth), not the onset. -1: none.
int OnsetFrame(const DicJSeries& s) {
  int onset = -1;
  for (size_t k = 0; k < s.image.size(); ++k) {
    if (s.delta_star_status[k] != "ok" || !std::isfinite(s.delta_star[k])) continue;
    if (!ZeroOpening(s, k)) {
      if (onset >= 0) break;
      continue;
    }
    onset = static_cast<int>(k);
  }
  return onset;
}

// The last frame of the onset's zero-opening run whose tip is measured at
// or behind the notch root (crack length <= a0), -1 when none. Frames of
// the run after it read delta* zero within its uncertainty with the tip
// past the root by less than the tip's uncertainty: growth there is not
// resolved, and may have begun after this frame (docs/LAW_FREE.md "Onset
// not resolved").
int LastFrameAtTheRoot(const DicJSeries& s, int onset) {
  if (onset < 0 || !std::isfinite(s.notch_length)) return -1;
  int at_root = -1;
  for (int k = 0; k <= onset; ++k) {
    if (!ZeroOpening(s, k)) continue;
    if (std::isfinite(s.crack_length[k]) && s.crack_length[k] <= s.notch_length) at_root = k;
  }
  return at_root;
}

// Frames after the onset that the DIC flagged (their crack geometry may be
// off by more than its uncertainty: a path that disagrees with the line,
// methods that disagree, ...): their delta* and J_ff are measured about that
// geometry (48-frame runs: delta* 3-9 um off on such frames, 0.5-1.3 um on
// the others). Skipped, with one note, when at least `min_points` usable
// frames remain; else kept with a warning. `usable(k)`: the frame would be
// a sample. Returns the frames to skip.
std::vector<char> FlaggedToSkip(const DicJSeries& s, int onset, int min_points,
                                const std::function<bool(size_t)>& usable, const char* route,
                                std::vector<std::string>& notes) {
  std::vector<char> skip(s.image.size(), 0);
  std::string listed;
  int flagged = 0, clean = 0;
  for (size_t k = 0; k < s.image.size(); ++k) {
    if (!usable(k)) continue;
    if (static_cast<int>(k) <= onset || s.flags[k].empty()) {
      ++clean;
      continue;
    }
    skip[k] = 1;
    ++flagged;
    listed += fmt::format("{}{} ({})", listed.empty() ? "" : ", ", k, s.flags[k]);
  }
  if (flagged == 0) return skip;
  if (clean >= min_points) {
    notes.push_back(fmt::format(
        "{} frame(s) the DIC flagged left out of the {} route (their tip or line may be off, and "
        "delta* and J_ff with it): {}",
        flagged, route, listed));
    return skip;
  }
  notes.push_back(fmt::format(
      "warning: {} frame(s) the DIC flagged are used by the {} route ({} unflagged, fewer than "
      "{}): their tip or line may be off, and delta* and J_ff with it: {}",
      flagged, route, clean, min_points, listed));
  return std::vector<char>(s.image.size(), 0);
}

// The onset not resolved (frames of the zero-opening run after `at_root`
// have their tip past the root): J_tip,c lies between J at `at_root` and at
// the onset frame; the onset sample takes the middle and half the range,
// with a warning. spread 0: resolved.
struct OnsetRange {
  double spread = 0, mid = NAN;
};
OnsetRange UnresolvedOnset(const DicJSeries& s, int onset, int at_root,
                           const std::function<double(size_t)>& j_of,
                           std::vector<std::string>& notes) {
  OnsetRange range;
  if (at_root < 0 || at_root >= onset) return range;
  const double j_root = j_of(at_root), j_onset = j_of(onset);
  if (!std::isfinite(j_root) || !std::isfinite(j_onset)) return range;
  range.spread = 0.5 * std::abs(j_onset - j_root);
  range.mid = 0.5 * (j_onset + j_root);
  notes.push_back(fmt::format(
      "warning: the onset of growth is not resolved: frames {}..{} read delta* zero within "
      "its uncertainty with the tip past the notch root (crack length {:.3f}..{:.3f} mm, "
      "a0 {:.3f} mm); growth may have begun after frame {}, so J_tip,c may lie anywhere "
      "from {:.1f} to {:.1f} J/m^2: the onset sample takes the middle, its uncertainty "
      "half that range (+-{:.1f} J/m^2); give --onset if the onset is known",
      at_root + 1, onset, s.crack_length[at_root + 1] * 1e3, s.crack_length[onset] * 1e3,
      s.notch_length * 1e3, at_root, j_root, j_onset, range.spread));
  return range;
}

// Frame k's opening uncertainty for the J route. A near-tip delta* reads
// high by up to half the bridging share W / J_ff (dic/frame_j.hpp), at most
// (J - j_ref) / J: beyond the allowance dic states, it is widened to that
// (counted in *widened).
double OpeningUncertainty(const DicJSeries& s, size_t k, double J, double j_ref, int* widened) {
  double ux = std::isfinite(s.delta_star_uncertainty[k]) ? s.delta_star_uncertainty[k] : 0.0;
  if (s.delta_star_method[k] != "near_tip") return ux;
  const double share = std::isfinite(j_ref) && J > 0 ? std::max(0.0, J - j_ref) / J : 1.0;
  if (0.5 * share <= dic::kNearTipModelRelative) return ux;
  ++*widened;
  return std::hypot(ux, 0.5 * share * s.delta_star[k]);
}

}  // namespace

// Frames with both J and delta* ok -> J route samples; the others skipped
// with a note each. Unless the request gives the onset, it is the onset
// frame (OnsetFrame): frames before it (J_tip still rising at the root) are
// left out with one note, and without such a frame the laws unit detects
// the onset from J_ff's shape, with a warning.
laws::FarFieldJSamples FarFieldJSamplesOf(const DicJSeries& s, const LawFreeRequest& request,
                                          std::vector<std::string>& notes) {
  laws::FarFieldJSamples out;
  const int onset = request.onset_opening ? -1 : OnsetFrame(s);
  int before = 0, from_domains = 0;
  const bool want_fit = request.j_source == LawFreeRequest::JSource::kFieldFit;
  // A frame's J_ff as its sample takes it: the field fit's where usable.
  auto fit_usable = [&](size_t k) {
    return want_fit && s.J_fit_status[k] == "ok" && std::isfinite(s.J_ff_fit[k]) &&
           std::isfinite(s.J_ff_fit_uncertainty[k]);
  };
  auto j_of = [&](size_t k) {
    return fit_usable(k) ? s.J_ff_fit[k] : s.J_status[k] == "ok" ? s.J_ff[k] : NAN;
  };
  const int at_root = LastFrameAtTheRoot(s, onset);
  const OnsetRange range = UnresolvedOnset(s, onset, at_root, j_of, notes);
  // J with the tip still at the root: J_tip,c >= it, so a later frame's
  // bridging share W / J_ff is at most (J - j_ref) / J (1 without it).
  const double j_ref = at_root >= 0 ? j_of(at_root) : onset >= 0 ? j_of(onset) : NAN;
  int widened_near_tip = 0;
  auto j_usable = [&](size_t k) {
    return fit_usable(k) || (s.J_status[k] == "ok" && std::isfinite(s.J_ff[k]));
  };
  auto d_usable = [&](size_t k) {
    return s.delta_star_status[k] == "ok" && std::isfinite(s.delta_star[k]);
  };
  const std::vector<char> flagged = FlaggedToSkip(
      s, onset, request.options.min_points,
      [&](size_t k) {
        return j_usable(k) && d_usable(k) && static_cast<int>(k) >= onset &&
               !(onset >= 0 && static_cast<int>(k) > onset && ZeroOpening(s, k));
      },
      "J", notes);
  for (size_t k = 0; k < s.image.size(); ++k) {
    const bool fit_ok = fit_usable(k);
    const bool j_ok = j_usable(k);
    const bool d_ok = d_usable(k);
    if (flagged[k]) continue;
    if (static_cast<int>(k) < onset && j_ok && d_ok) {
      ++before;
      continue;
    }
    if (onset >= 0 && static_cast<int>(k) > onset && ZeroOpening(s, k)) {
      notes.push_back(fmt::format(
          "warning: frame {} ({}) reads delta* = 0 after growth began at frame {}: skipped", k,
          s.image[k], onset));
      continue;
    }
    if (!j_ok || !d_ok) {
      if (s.J_status[k].rfind("no_tip", 0) != 0 || k > 0)
        notes.push_back(fmt::format("frame {} ({}) skipped: J {}, delta* {}", k, s.image[k],
                                    s.J_status[k], s.delta_star_status[k]));
      if (static_cast<int>(k) == onset)
        notes.push_back(fmt::format(
            "warning: the onset frame {} (delta* = 0) has no J_ff: the onset is taken at the "
            "next usable frame, openings and J_tip,c are counted from there",
            k));
      continue;
    }
    const bool is_onset = static_cast<int>(k) >= onset && onset >= 0 && !out.onset_index;
    if (is_onset) out.onset_index = static_cast<int>(out.opening.size());
    // The onset frame's opening is zero within its uncertainty: the onset
    // is delta* = 0 by definition, and the laws count openings from it.
    const bool zero_onset = is_onset && static_cast<int>(k) == onset;
    out.opening.push_back(zero_onset ? 0.0 : s.delta_star[k]);
    out.opening_uncertainty.push_back(
        zero_onset ? 0.0 : OpeningUncertainty(s, k, j_of(k), j_ref, &widened_near_tip));
    if (fit_ok) {
      out.J_ff.push_back(s.J_ff_fit[k]);
      out.uncertainty.push_back(std::max(s.J_ff_fit_uncertainty[k],
                                         request.j_fit_relative_floor * std::abs(s.J_ff_fit[k])));
    } else {
      // A fit that ran and failed is noted per frame; a file without fits
      // (older, or the fit off) only in the count below.
      const std::string& fs = s.J_fit_status[k];
      if (want_fit && fs != "missing" && fs != "not_requested")
        notes.push_back(fmt::format("frame {} ({}): J_ff from the domains (field fit: {})", k,
                                    s.image[k], fs));
      from_domains += want_fit;
      const double spread =
          std::isfinite(s.J_ff_spread_percent[k]) ? s.J_ff_spread_percent[k] : 0;
      out.J_ff.push_back(s.J_ff[k]);
      out.uncertainty.push_back(std::max(0.5 * spread / 100, request.j_relative_floor) *
                                std::abs(s.J_ff[k]));
    }
    if (is_onset && range.spread > 0) {
      out.J_ff.back() = range.mid;
      out.uncertainty.back() = std::hypot(out.uncertainty.back(), range.spread);
    }
  }
  // Frames whose field showed a uniform dilatation (taken out of J_ff):
  // the test moved out of plane or changed temperature.
  std::string dilated;
  int dilated_count = 0;
  for (size_t k = 0; k < s.J_fit_dilatation_removed.size(); ++k)
    if (s.J_fit_dilatation_removed[k] > 0) {
      ++dilated_count;
      if (dilated_count <= 5)
        dilated += fmt::format("{}frame {} {:.2g} +- {:.1g}", dilated.empty() ? "" : ", ", k,
                               s.J_fit_dilatation[k], s.J_fit_dilatation_uncertainty[k]);
    }
  if (dilated_count > 0)
    notes.push_back(fmt::format(
        "warning: {} frame(s) show a uniform dilatation of the field ({}{}), taken out of their "
        "J_ff as stress-free: a 2D DIC reads a specimen moving towards the camera (dz / working "
        "distance) or a temperature change so; on the other frames one below 3 standard "
        "uncertainties stays in J_ff (docs/LAW_FREE.md)",
        dilated_count, dilated, dilated_count > 5 ? ", ..." : ""));
  notes.push_back(want_fit ? fmt::format("J_ff per frame: the field-wide fit's ({} of {} frames "
                                         "from the domains)",
                                         from_domains, out.J_ff.size())
                           : std::string("J_ff per frame: the domains' (--j-source domains)"));
  if (widened_near_tip > 0)
    notes.push_back(fmt::format(
        "{} frame(s) read delta* from the near-tip opening (tip past the root by less than "
        "the profile's stretch) while bridging may carry more than {:.0f} % of J_ff: their "
        "opening uncertainty includes half that share (the relation reads high by up to it)",
        widened_near_tip, 200 * dic::kNearTipModelRelative));
  out.onset_opening = request.onset_opening;
  if (request.onset_opening) return out;
  if (onset >= 0) {
    notes.push_back(fmt::format(
        "onset of growth: frame {} ({}), the last with delta* = 0 within its uncertainty{}", onset,
        s.image[onset],
        before > 0 ? fmt::format("; {} frame(s) before it left out (J_tip still rising)", before)
                   : std::string()));
  } else {
    notes.push_back(
        "warning: no frame has delta* = 0 within its uncertainty (the crack had grown before "
        "the first frame with J and delta*, or that frame failed): the onset of growth is "
        "detected from the shape of J_ff(delta*), which a smooth drift of J_ff can fool; give "
        "--onset");
  }
  return out;
}

namespace {

// R points -> (delta_root, R): delta* per frame interpolated linearly in
// crack length (frames at one length averaged), never extrapolated.
laws::RCurveSamples RSamples(const DicJSeries& s, const RCurve& rc, const LawFreeRequest& request,
                             std::vector<std::string>& notes) {
  auto usable = [&](size_t k) {
    return s.delta_star_status[k] == "ok" && std::isfinite(s.delta_star[k]) &&
           std::isfinite(s.crack_length[k]);
  };
  // Frames the DIC flagged: their delta* is doubtful here too (FlaggedToSkip).
  const std::vector<char> flagged =
      FlaggedToSkip(s, -1, request.options.min_points, usable, "R", notes);
  std::map<double, std::pair<double, int>> by_length;  // a -> (sum delta, count)
  for (size_t k = 0; k < s.image.size(); ++k)
    if (usable(k) && !flagged[k]) {
      auto& e = by_length[s.crack_length[k]];
      e.first += s.delta_star[k];
      ++e.second;
    }
  laws::RCurveSamples out;
  out.J_tip_c = request.J_tip_c;
  if (by_length.size() < 2) {
    notes.push_back("R route: fewer than two frames with delta* and a crack length");
    return out;
  }
  std::vector<double> a, d;
  for (const auto& [length, e] : by_length) {
    a.push_back(length);
    d.push_back(e.first / e.second);
  }
  std::vector<double> sorted_R(rc.R);
  std::sort(sorted_R.begin(), sorted_R.end());
  const double median_R = sorted_R.empty() ? 0 : sorted_R[sorted_R.size() / 2];
  const bool has_u = rc.R_uncertainty.size() == rc.R.size();
  if (!has_u)
    notes.push_back(fmt::format("R route: the R curve has no uncertainty; {:.0f}% of the median R "
                                "({:.4g} J/m^2) assumed",
                                100 * request.r_relative_floor, median_R));
  int outside = 0;
  for (size_t i = 0; i < rc.R.size(); ++i) {
    const double ai = rc.crack_length[i];
    if (!(ai >= a.front() && ai <= a.back()) || !std::isfinite(rc.R[i])) {
      ++outside;
      continue;
    }
    const size_t j = std::min<size_t>(
        std::upper_bound(a.begin(), a.end(), ai) - a.begin(), a.size() - 1);
    const double t = (ai - a[j - 1]) / (a[j] - a[j - 1]);
    out.opening.push_back(d[j - 1] + t * (d[j] - d[j - 1]));
    out.R.push_back(rc.R[i]);
    const double u = has_u ? rc.R_uncertainty[i] / rc.uncertainty_coverage : 0;
    out.uncertainty.push_back(u > 0 ? u : request.r_relative_floor * std::abs(median_R));
  }
  if (outside > 0)
    notes.push_back(fmt::format(
        "R route: {} of {} R points outside the frames' crack lengths {:.4g}-{:.4g} mm skipped",
        outside, rc.R.size(), a.front() * 1e3, a.back() * 1e3));
  // Equal openings (points between two frames of equal delta*) would repeat.
  return out;
}

}  // namespace

LawFreeRun RunLawFree(const LawFreeRequest& request) {
  std::string why;
  if (!request.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid law-free request: " + why);
  Stopwatch watch;
  LawFreeRun run;
  run.dic_file = request.dic_file.string();
  run.rcurve_file = request.rcurve_file.string();
  const DicJSeries series = ReadDicJSeries(request.dic_file);
  run.frames = static_cast<int>(series.image.size());
  std::vector<std::string> failures;
  if (request.far_field_route) {
    run.j_samples = FarFieldJSamplesOf(series, request, run.notes);
    try {
      run.far_field = laws::LawFromFarFieldJ(run.j_samples, request.options);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::kUsage) throw;
      failures.push_back("J_ff route: " + e.message());
    }
  }
  if (!request.rcurve_file.empty()) {
    const RCurve rc = ReadRCurveFile(request.rcurve_file.string());
    run.r_samples = RSamples(series, rc, request, run.notes);
    try {
      run.r_curve = laws::LawFromRCurve(run.r_samples, request.options);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::kUsage) throw;
      failures.push_back("R route: " + e.message());
    }
  }
  if (!run.far_field && !run.r_curve) {
    std::string all;
    for (const std::string& f : failures) all += (all.empty() ? "" : "; ") + f;
    throw Error(ErrorKind::kInput, "no law-free route could run: " + all,
                {.file = run.dic_file,
                 .expected = "at least min_points frames with J_ff and delta* status ok"});
  }
  for (const std::string& f : failures) run.notes.push_back(f);
  run.wall_s = watch.Seconds();
  return run;
}

std::string LawFreeRun::BriefReport() const {
  std::string s = fmt::format("law-free bridging law from {} ({} frames){}\n", dic_file, frames,
                              rcurve_file.empty() ? "" : " and " + rcurve_file);
  auto route = [&](const char* name, const std::optional<laws::LawFreeResult>& r) {
    if (!r) return;
    s += fmt::format("{}:\n", name);
    s += r->Summary();
  };
  route("J_ff(delta*) route (eq. 1)", far_field);
  route("R(delta_root) route (eq. 3)", r_curve);
  for (const std::string& n : notes) s += "  note: " + n + "\n";
  s += fmt::format("({:.2f} s)\n", wall_s);
  return s;
}

}  // namespace bridgefit::pipeline
