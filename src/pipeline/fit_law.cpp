// The law a fit fits (fit.hpp, fit_models.hpp): the `--law` rule, a
// fitted-shape family alone, and the fitted shape as the run carries and
// prints it (issue 21).
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "fit_models.hpp"

namespace bridgefit::pipeline {

void SetFitLaw(const std::string& text, FitRequest& request) {
  if (text == "compare") {
    request.compare_laws = true;
    request.shape_law.reset();
    return;
  }
  for (inverse::ShapeFamily family : {inverse::ShapeFamily::kBilinear,
                                      inverse::ShapeFamily::kTrilinear, inverse::ShapeFamily::kTable})
    if (text == inverse::ShapeFamilyName(family)) {
      request.compare_laws = false;
      request.shape_law = family;
      request.law = family == inverse::ShapeFamily::kTrilinear ? laws::LawFamily::kTrilinear
                                                                : laws::LawFamily::kTable;
      return;
    }
  try {
    request.law = laws::ParseLawFamily(text);  // the request unchanged when it throws
    request.compare_laws = false;
    request.shape_law.reset();
  } catch (const Error& e) {
    throw Error(ErrorKind::kUsage, e.message(),
                {.field = "--law", .value = text,
                 .expected = "linear, cubic, triangular or exponential (shape held); bilinear, "
                             "trilinear or table (shape fitted too); or compare (AICc)"});
  }
}

// `--law bilinear|trilinear|table`: the family's shape fitted with the scale
// parameters (the table's N by AICc); data too few for every N it may try
// are an input error naming the way out.
void FitShapeAlone(const FitRequest& request, const inverse::ForwardModel& model,
                   const inverse::FitData& fit_data, const inverse::FitOptions& options,
                   FitRun& run) {
  const inverse::ShapeFamily family = *request.shape_law;
  inverse::ShapeFit f =
      family == inverse::ShapeFamily::kTable
          ? inverse::FitTableLaw(model, fit_data, options, request.shape_fit)
          : inverse::FitShapeFamily(model, family, fit_data, options, request.shape_fit);
  if (!f.fitted)
    throw Error(ErrorKind::kInput, "the data are too few for this law's shape: " + f.skip_reason,
                {.file = run.input.label, .field = "--law", .value = f.law,
                 .expected = family == inverse::ShapeFamily::kTable
                                 ? "more points, fewer knots (e.g. --table-knots 2,3), or a law "
                                   "whose shape is held (--law linear|cubic)"
                                 : "more points, or a law whose shape is held (--law linear|cubic)"});
  run.summary = std::move(f.summary);
  run.summary.wall_s = f.wall_s;  // with the seed fits and every N tried
  run.shape = std::move(f.shape);
  run.fitted_shape.family = f.law;
  run.fitted_shape.parameters = std::move(f.shape_parameters);
  run.fitted_shape.knots = f.knots;
  run.fitted_shape.note = std::move(f.note);
}

FittedShape FittedShapeOf(const inverse::LawComparison& c) {
  FittedShape f;
  if (c.shape_parameters.empty()) return f;  // a fixed-shape family
  f.family = c.law;
  f.parameters = c.shape_parameters;
  f.knots = c.law == "table" ? static_cast<int>(c.shape.d_points.size()) - 1 : 0;
  f.note = c.note;
  return f;
}

// The fitted shape's parameters as the summary prints them: each with its
// Wald 95% interval (1.96 se, the scale parameters free), said as such.
std::string FittedShapeText(const FittedShape& f, const inverse::FitSummary& s) {
  std::string out = fmt::format("  {} shape (d = delta / delta_c, s = sigma / sigma_c){}:\n",
                                f.family, f.knots > 0 ? fmt::format(", N = {} knots", f.knots) : "");
  const double sigma_c = s.sigma_c.value, delta_c = s.delta_c.value;
  for (const inverse::ShapeParameter& p : f.parameters) {
    const bool position = p.name.rfind('d', 0) == 0;
    out += fmt::format("    {:<9} {:.4f}", p.name, p.value);
    if (p.pinned)
      out += "  (the peak: sigma_c by definition)";
    else if (std::isfinite(p.standard_error))
      out += fmt::format("  95% Wald [{:.4f}, {:.4f}]", p.value - 1.96 * p.standard_error,
                         p.value + 1.96 * p.standard_error);
    else
      out += "  (Wald interval: singular information)";
    if (position && std::isfinite(delta_c))
      out += fmt::format("  delta {:.4g} mm", p.value * delta_c * 1e3);
    else if (!position && std::isfinite(sigma_c))
      out += fmt::format("  sigma {:.4g} MPa", p.value * sigma_c * 1e-6);
    out += "\n";
  }
  if (!f.note.empty()) out += "    " + f.note + "\n";
  return out;
}

}  // namespace bridgefit::pipeline
