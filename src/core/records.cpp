#include "bridgefit/core/records.hpp"

#include <algorithm>
#include <string>

#include "bridgefit/core/error.hpp"

namespace bridgefit {
namespace {

void CheckColumn(const std::string& source, const char* name, const std::vector<double>& column,
                 std::size_t expected_size, bool may_be_empty, bool may_hold_nan = false) {
  if (column.empty() && may_be_empty) return;
  if (column.size() != expected_size)
    throw Error(ErrorKind::kInput, "column length differs from the load column",
                {.file = source, .field = name, .value = std::to_string(column.size()) + " rows",
                 .expected = std::to_string(expected_size) + " rows"});
  for (std::size_t i = 0; i < column.size(); ++i)
    if (!std::isfinite(column[i]) && !(may_hold_nan && std::isnan(column[i])))
      throw Error(ErrorKind::kInput, "value is not finite in row " + std::to_string(i + 1),
                  {.file = source, .field = name, .value = std::to_string(column[i])});
}

}  // namespace

void ExperimentRecord::Validate() const {
  const std::size_t n = load.size();
  CheckColumn(source, "load", load, n, false);
  CheckColumn(source, "displacement", displacement, n, false);
  CheckColumn(source, "time", time, n, true);
  // A crack length may be missing (NaN) in some rows: the R-curve methods
  // that need it take those rows out and count them.
  CheckColumn(source, "crack_length", crack_length, n, true, true);
  if (!images.empty() && images.size() != n)
    throw Error(ErrorKind::kInput, "image column length differs from the load column",
                {.file = source, .field = "image"});
}

void RCurve::Validate() const {
  const std::size_t n = R.size();
  CheckColumn(source, "crack_length", crack_length, n, false);
  CheckColumn(source, "R", R, n, false);
  CheckColumn(source, "R_uncertainty", R_uncertainty, n, true);
}

const char* RunStatusName(RunStatus status) {
  switch (status) {
    case RunStatus::kOk: return "ok";
    case RunStatus::kNotConverged: return "not_converged";
    case RunStatus::kUnstable: return "unstable";
    case RunStatus::kInvalidInput: return "invalid_input";
    case RunStatus::kFailed: return "failed";
  }
  return "unknown";
}

RCurve SimulationResult::ToRCurve(bool energy_kind) const {
  RCurve curve;
  curve.method = model;
  curve.r_kind = energy_kind ? "energy" : "elastic-zone";
  curve.source = "simulation (" + model + ")";
  for (const SimulationPoint& p : points) {
    const double r = energy_kind ? p.R_energy : p.R;
    if (!std::isfinite(r)) continue;
    curve.crack_length.push_back(p.crack_length);
    curve.R.push_back(r);
  }
  if (!points.empty()) curve.initial_crack_length = points.front().crack_length;
  return curve;
}

double InterpolatePoints(const std::vector<SimulationPoint>& points, double a,
                         double SimulationPoint::*field) {
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const double a0 = points[i].crack_length, a1 = points[i + 1].crack_length;
    if (a >= a0 - 1e-12 && a <= a1 + 1e-12 && a1 > a0) {
      const double f = (a - a0) / (a1 - a0);
      return (1 - f) * points[i].*field + f * points[i + 1].*field;
    }
  }
  return NAN;
}

void FillEnergyR(std::vector<SimulationPoint>& points, double thickness) {
  const size_t n = points.size();
  std::vector<double> step(n > 0 ? n - 1 : 0, NAN);
  for (size_t i = 0; i + 1 < n; ++i) {
    const SimulationPoint& a = points[i];
    const SimulationPoint& b = points[i + 1];
    const double work = 0.5 * (a.load + b.load) * (b.displacement - a.displacement);
    const double stored = 0.5 * (b.load * b.displacement - a.load * a.displacement);
    step[i] = (work - stored) / (thickness * (b.crack_length - a.crack_length));
  }
  for (size_t i = 0; i < n; ++i) {
    if (n < 2) break;
    if (i == 0) points[i].R_energy = step[0];
    else if (i + 1 == n) points[i].R_energy = step[n - 2];
    else points[i].R_energy = 0.5 * (step[i - 1] + step[i]);
  }
}

ExperimentRecord RecordAlongPath(const SimulationResult& sim, int loading_rows, int growth_rows,
                                 std::vector<std::size_t>* nearest_point) {
  const std::vector<SimulationPoint>& points = sim.points;
  if (points.size() < 2 || growth_rows < 2 || loading_rows < 0)
    throw Error(ErrorKind::kUsage, "a record along a path needs two points and two growth rows");
  ExperimentRecord record;
  record.source = "simulation (" + sim.model + ")";
  auto add = [&record](double load, double displacement, double crack_length) {
    record.load.push_back(load);
    record.displacement.push_back(displacement);
    record.crack_length.push_back(crack_length);
  };
  const SimulationPoint& first = points.front();
  for (int i = 0; i < loading_rows; ++i) {
    const double f = static_cast<double>(i) / loading_rows;
    add(f * first.load, f * first.displacement, first.crack_length);
  }
  if (nearest_point) nearest_point->clear();
  const std::size_t n = points.size();
  for (int i = 0; i < growth_rows; ++i) {
    const double s = double(i) * (n - 1) / (growth_rows - 1);
    const std::size_t k = std::min(static_cast<std::size_t>(s), n - 2);
    const double w = s - k;
    const SimulationPoint& p = points[k];
    const SimulationPoint& q = points[k + 1];
    add(p.load + w * (q.load - p.load), p.displacement + w * (q.displacement - p.displacement),
        p.crack_length + w * (q.crack_length - p.crack_length));
    if (nearest_point) nearest_point->push_back(w < 0.5 ? k : k + 1);
  }
  return record;
}

}  // namespace bridgefit
