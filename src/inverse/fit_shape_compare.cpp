// Fitted-shape families one by one, the table's knot count by AICc, and
// `--law compare` over them and the fixed-shape families (fit_shape.hpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "fit_shape_impl.hpp"

namespace bridgefit::inverse {

using namespace shape_internal;

const char* ShapeFamilyName(ShapeFamily family) {
  switch (family) {
    case ShapeFamily::kBilinear:
      return "bilinear";
    case ShapeFamily::kTrilinear:
      return "trilinear";
    case ShapeFamily::kTable:
      return "table";
  }
  return "table";
}

bool ShapeFitOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (table_knots.empty()) return fail("table_knots: at least one knot count");
  for (int n : table_knots)
    if (n < 2 || n > 20) return fail(fmt::format("table_knots: {} not in 2 .. 20", n));
  if (!(smoothness >= 0.0) || !std::isfinite(smoothness)) return fail("smoothness must be >= 0");
  if (random_starts < 0 || seed_starts < 0)
    return fail("random_starts and seed_starts must be >= 0");
  if (random_starts + seed_starts < 1) return fail("at least one start");
  if (max_evaluations < 10) return fail("max_evaluations must be >= 10");
  return true;
}

std::string ShapeFit::BriefReport() const {
  if (!fitted) return fmt::format("{}: not fitted: {}\n", law, skip_reason);
  std::string out = fmt::format("{} law: {} parameters", law, parameters);
  if (penalty > 0.0)
    out += fmt::format(" ({:.2f} effective, lambda {:.3g})", effective_parameters, penalty);
  out += fmt::format(", chi2 {:.4g}\n", summary.chi2);
  for (const ShapeParameter& p : shape_parameters) {
    out += fmt::format("  {:<9} {:.4f}", p.name, p.value);
    if (p.pinned)
      out += "  (the peak: sigma_c)";
    else
      out += fmt::format("  +- {:.4f} (Wald, 1.96 se)", 1.96 * p.standard_error);
    if (family != ShapeFamily::kTable || p.name.rfind("s(", 0) != 0 ||
        !std::isfinite(summary.sigma_c.value))
      out += "\n";
    else
      out += fmt::format("  sigma {:.4g} MPa\n", p.value * summary.sigma_c.value * 1e-6);
  }
  if (!note.empty()) out += "  " + note + "\n";
  return out;
}

namespace shape_internal {

double SeedScale(const FitData& data, const std::vector<LawComparison>& seeds) {
  if (data.weighted()) return 1.0;
  double best = INFINITY;
  for (const LawComparison& c : seeds)
    if (c.summary.converged)
      best = std::min(best, c.summary.chi2 / std::max(1, c.summary.data_points - 3));
  return std::isfinite(best) && best > 0.0 ? best : 1.0;
}

std::vector<LawComparison> SeedFits(const ForwardModel& model, const FitData& data,
                                    const FitOptions& options) {
  FitOptions quick = options;
  quick.profile_likelihood = false;
  return CompareLawFamilies(model, {laws::MakeLinearShape(), laws::MakeCubicShape()}, data, quick);
}

}  // namespace shape_internal

namespace {

void Check(const FitData& data, const FitOptions& options, const ShapeFitOptions& shape_options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid fit options: " + why);
  if (!shape_options.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid shape-fit options: " + why);
  data.Validate();
}

}  // namespace

ShapeFit FitShapeFamily(const ForwardModel& model, ShapeFamily family, const FitData& data,
                        const FitOptions& options, const ShapeFitOptions& shape_options, int knots,
                        const std::vector<LawComparison>* seeds, double scale2) {
  Check(data, options, shape_options);
  BF_CHECK_INPUT(family != ShapeFamily::kTable || (knots >= 2 && knots <= 20),
                 "a table law needs 2 to 20 knots",
                 {.field = "knots", .value = std::to_string(knots)});
  const Stopwatch clock;
  const ShapeLayout layout{family, family == ShapeFamily::kTable ? knots : 0,
                           shape_options.table_interpolation};
  const int k = static_cast<int>(FreeScaleParameters(options).size()) + layout.counted();
  const std::string name =
      family == ShapeFamily::kTable ? fmt::format("table N = {}", knots) : ShapeFamilyName(family);
  ShapeFit out;
  out.family = family;
  out.law = ShapeFamilyName(family);
  out.parameters = k;
  out.skip_reason = TooFewPoints(static_cast<int>(data.size()), k, name);
  if (!out.skip_reason.empty()) return out;
  const std::vector<LawComparison> own =
      seeds ? std::vector<LawComparison>{} : SeedFits(model, data, options);
  const std::vector<LawComparison>& start_from = seeds ? *seeds : own;
  if (!std::isfinite(scale2)) scale2 = SeedScale(data, start_from);
  out = FinishShapeFit(model, data, options,
                       RunJoint(model, layout, data, options, shape_options, start_from, scale2));
  out.wall_s = clock.Seconds();
  return out;
}

ShapeFit FitTableLaw(const ForwardModel& model, const FitData& data, const FitOptions& options,
                     const ShapeFitOptions& shape_options, const std::vector<LawComparison>* seeds,
                     double scale2) {
  Check(data, options, shape_options);
  const Stopwatch clock;
  const std::vector<LawComparison> own =
      seeds ? std::vector<LawComparison>{} : SeedFits(model, data, options);
  const std::vector<LawComparison>& start_from = seeds ? *seeds : own;
  if (!std::isfinite(scale2)) scale2 = SeedScale(data, start_from);
  const int n = static_cast<int>(data.size());
  const int n_main = static_cast<int>(FreeScaleParameters(options).size());
  ShapeFit out;
  out.family = ShapeFamily::kTable;
  out.law = ShapeFamilyName(ShapeFamily::kTable);
  std::vector<std::string> skipped;
  JointResult best;
  double best_aicc = INFINITY;
  int evaluations = 0;
  for (int knots : shape_options.table_knots) {
    const ShapeLayout layout{ShapeFamily::kTable, knots, shape_options.table_interpolation};
    out.knots_tried.push_back(knots);
    out.knots_aicc.push_back(NAN);
    const std::string why =
        TooFewPoints(n, n_main + layout.counted(), fmt::format("table N = {}", knots));
    if (!why.empty()) {
      skipped.push_back(why);
      continue;
    }
    JointResult j = RunJoint(model, layout, data, options, shape_options, start_from, scale2);
    evaluations += j.evaluations;
    if (!j.ok) {
      skipped.push_back(fmt::format("table N = {}: {}", knots, j.stop_reason));
      continue;
    }
    out.knots_aicc.back() = Aicc(j.chi2 / scale2, j.effective_parameters, n);
    if (out.knots_aicc.back() < best_aicc) best_aicc = out.knots_aicc.back(), best = std::move(j);
  }
  if (!best.ok) {
    out.skip_reason =
        skipped.empty() ? "no knot count to try" : fmt::format("{}", fmt::join(skipped, "; "));
    out.wall_s = clock.Seconds();
    return out;
  }
  ShapeFit chosen = FinishShapeFit(model, data, options, best);
  chosen.knots_tried = out.knots_tried;
  chosen.knots_aicc = out.knots_aicc;
  chosen.summary.evaluations += evaluations - best.evaluations;  // the other knot counts' searches
  chosen.evaluations = evaluations;
  std::string tried;
  for (size_t i = 0; i < out.knots_tried.size(); ++i)
    tried += fmt::format("{}N={} {:.2f}", i ? ", " : "", out.knots_tried[i], out.knots_aicc[i]);
  std::string note = fmt::format("N = {} knots chosen by AICc ({})", best.layout.knots, tried);
  if (!skipped.empty()) note += "; skipped: " + fmt::format("{}", fmt::join(skipped, "; "));
  chosen.note = chosen.note.empty() ? note : note + "; " + chosen.note;
  chosen.wall_s = clock.Seconds();
  return chosen;
}

void RankByAicc(std::vector<LawComparison>& comparison) {
  double best = INFINITY;
  for (const LawComparison& c : comparison)
    if (std::isfinite(c.aicc)) best = std::min(best, c.aicc);
  double total = 0.0;
  for (LawComparison& c : comparison) {
    c.delta_aicc = c.aicc - best;
    c.weight = std::isfinite(c.delta_aicc) ? std::exp(-0.5 * c.delta_aicc) : 0.0;
    total += c.weight;
  }
  for (LawComparison& c : comparison) c.weight = total > 0.0 ? c.weight / total : NAN;
}

std::vector<LawComparison> CompareLawFamiliesWithShapes(const ForwardModel& model,
                                                        const std::vector<laws::LawShape>& shapes,
                                                        const std::vector<ShapeFamily>& families,
                                                        const FitData& data,
                                                        const FitOptions& options,
                                                        const ShapeFitOptions& shape_options) {
  Check(data, options, shape_options);
  std::vector<LawComparison> out = shapes.empty()
                                       ? std::vector<LawComparison>{}
                                       : CompareLawFamilies(model, shapes, data, options);
  const std::vector<LawComparison> seeds = shapes.empty() ? SeedFits(model, data, options) : out;
  const double scale2 = out.empty() ? SeedScale(data, seeds) : out.front().noise_scale2;
  for (ShapeFamily family : families) {
    const ShapeFit f =
        family == ShapeFamily::kTable
            ? FitTableLaw(model, data, options, shape_options, &seeds, scale2)
            : FitShapeFamily(model, family, data, options, shape_options, 0, &seeds, scale2);
    LawComparison c;
    c.law = f.law;
    c.shape = f.shape;
    c.summary = f.summary;
    c.noise_scale2 = scale2;
    c.shape_parameters = f.shape_parameters;
    if (!f.fitted) {
      c.note = "skipped: " + f.skip_reason;
      c.summary.law = f.law;
      c.summary.converged = false;
      c.summary.verdict = c.note;
    } else {
      c.summary.wall_s = f.wall_s;
      c.parameters = c.summary.bridging_detected ? f.effective_parameters
                                                 : (options.fixed[kJTipC] ? 0.0 : 1.0);
      std::string shape_text;
      for (const ShapeParameter& p : f.shape_parameters)
        shape_text += fmt::format("{}{} {:.3g}", shape_text.empty() ? "" : ", ", p.name, p.value);
      c.note = f.note.empty() ? shape_text : shape_text + "; " + f.note;
      if (c.summary.converged)
        c.aicc = Aicc(c.summary.chi2 / scale2, c.parameters, c.summary.data_points);
    }
    out.push_back(std::move(c));
  }
  RankByAicc(out);
  return out;
}

}  // namespace bridgefit::inverse
