// The energy method (PHYSICS 8): dU = int P dd - (P_j d_j - P_i d_i)/2 between
// the ends of each crack increment, R = dU / (B da); optionally on local
// quadratic fits of the growth rows (ASTM E647 incremental polynomial).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "rcurve_stages.hpp"

namespace bridgefit::experiment::detail {

void EnergyMethod(const Prepared& p, RCurveResult& result) {
  {
    const RCurveOptions& options = *p.options;
    const ExperimentRecord& record = *p.record;
    const Rows& w = p.w;
    const int m = static_cast<int>(w.size());
    const double sigma_P = p.sigma_P, sigma_d = p.sigma_d, sigma_a = p.sigma_a, B = p.B, a0 = p.a0;
    const double k_cov = options.coverage_factor;
    const LinearFit& lin = p.lin;
    const int first_growth = p.first_growth;
    const int h = options.smoothing_half_window;
    // The increment is set by the crack readings' own scatter about a smooth
    // monotone fit (p.sigma_a_increment); the uncertainty keeps sigma_a, which
    // on a DCB also holds the compliance-law residual (lagging tracking).
    const double da_min = std::max(options.min_crack_increment,
                                   options.increment_resolution * std::sqrt(2.0) * p.sigma_a_increment);
    std::vector<double> ds(m);
    for (int k = 0; k < m; ++k) ds[k] = w.d[k] - lin.intercept;  // elastic unloading to d0
    const int start = std::max(0, first_growth - 1);
    AddDropped(result, "before initiation (no crack growth yet)", start);
    // Values entering the balance: the rows as measured, or (h > 0) local
    // quadratic fits against time over the growth rows [start, m - 1] only,
    // so no window straddles the initiation kink.
    std::vector<double> P_e = w.P, d_e = ds, a_e = w.a;
    std::vector<LocalWeights> fit_weights;  // per row from start (h > 0)
    if (h > 0) {
      std::vector<double> x(m);
      bool time_increases = !record.time.empty();
      for (int k = 0; k < m; ++k) {
        x[k] = time_increases ? record.time[w.row[k]] : k;
        if (k > start && !(x[k] > x[k - 1])) time_increases = false;
      }
      if (!time_increases)
        for (int k = 0; k < m; ++k) x[k] = k;
      double hat_sum = 0.0;
      for (int k = start; k < m; ++k) {
        LocalWeights lw = LocalQuadraticWeights(x, start, m - 1, k, h);
        double p = 0.0, d = 0.0, a = 0.0, hat = 0.0;
        for (std::size_t q = 0; q < lw.weights.size(); ++q) {
          const int r = lw.first_row + static_cast<int>(q);
          p += lw.weights[q] * w.P[r];
          d += lw.weights[q] * ds[r];
          a += lw.weights[q] * w.a_raw[r];
          hat += lw.weights[q] * lw.weights[q];
        }
        P_e[k] = p, d_e[k] = d, a_e[k] = a;
        hat_sum += std::sqrt(hat);
        fit_weights.push_back(std::move(lw));
      }
      const double noise_factor = hat_sum / (m - start);  // mean sqrt(sum w^2)
      result.figures["energy_smoothing_half_window_rows"] = h;
      result.figures["energy_smoothed_crack_noise_m"] = noise_factor * sigma_a;
      result.notes.push_back(fmt::format(
          "energy method on local quadratic fits of load, displacement and crack length against {} "
          "over {} rows (ASTM E647 incremental polynomial); crack-length noise {} per row, {} "
          "after the fits; every increment spans at least one window",
          time_increases ? "time" : "row number", 2 * h + 1, Mm(sigma_a), Mm(noise_factor * sigma_a)));
    }
    // Standard deviation of a_e[j] - a_e[i] over sigma_a: sqrt 2 for raw rows,
    // the norm of the difference of the two fits' weights when smoothed.
    std::vector<double> dense(h > 0 ? m : 0, 0.0);
    auto da_noise_factor = [&](int i, int j) {
      if (h <= 0) return std::sqrt(2.0);
      const LocalWeights& wi = fit_weights[i - start];
      const LocalWeights& wj = fit_weights[j - start];
      for (std::size_t q = 0; q < wj.weights.size(); ++q) dense[wj.first_row + q] += wj.weights[q];
      for (std::size_t q = 0; q < wi.weights.size(); ++q) dense[wi.first_row + q] -= wi.weights[q];
      double ss = 0.0;
      const int lo = std::min(wi.first_row, wj.first_row);
      const int hi = std::max(wi.first_row + static_cast<int>(wi.weights.size()),
                              wj.first_row + static_cast<int>(wj.weights.size()));
      for (int r = lo; r < hi; ++r) ss += dense[r] * dense[r], dense[r] = 0.0;
      return std::sqrt(ss);
    };
    // Increments [i, j]: each the shortest run with da >= da_min (smoothed:
    // da >= max(min_crack_increment, increment_resolution x its own noise)
    // and at least one window of rows); rows left over at the end join the
    // last increment.
    auto resolvable = [&](int i, int j) {
      const double da = a_e[j] - a_e[i];
      if (h <= 0) return da >= da_min;
      return j - i >= 2 * h + 1 && da >= options.min_crack_increment &&
             da >= options.increment_resolution * sigma_a * da_noise_factor(i, j);
    };
    result.figures["energy_min_increment_m"] = h > 0 ? options.min_crack_increment : da_min;
    std::vector<std::pair<int, int>> increments;
    for (int i = start;;) {
      int j = i + 1;
      while (j < m && !resolvable(i, j)) ++j;
      if (j >= m) break;
      increments.emplace_back(i, j);
      i = j;
    }
    if (!increments.empty() && increments.back().second < m - 1 &&
        a_e[m - 1] > a_e[increments.back().second]) {
      result.notes.push_back(fmt::format("the last {} rows (growth {}) joined the last increment",
                                         m - 1 - increments.back().second,
                                         Mm(a_e[m - 1] - a_e[increments.back().second])));
      increments.back().second = m - 1;
    }
    std::vector<double> gP(h > 0 ? m : 0, 0.0), gd(h > 0 ? m : 0, 0.0);
    int last_end = start;
    for (const auto& [i, j] : increments) {
      const double da = a_e[j] - a_e[i];
      const double dU = EnergyReleased(P_e, d_e, i, j);
      const double R = dU / (B * da);
      // Linear sensitivities of dU to every P_k and d_k of the increment
      // (smoothed: carried back to the measured rows through the fits' weights).
      double var = 0.0;
      for (int k = i; k <= j; ++k) {
        const double dprev = k > i ? d_e[k] - d_e[k - 1] : 0.0;
        const double dnext = k < j ? d_e[k + 1] - d_e[k] : 0.0;
        double sP = 0.5 * (dprev + dnext);
        const double Pprev = k > i ? P_e[k - 1] : P_e[k];
        const double Pnext = k < j ? P_e[k + 1] : P_e[k];
        double sd = (k > i ? 0.5 * (Pprev + P_e[k]) : 0.0) - (k < j ? 0.5 * (P_e[k] + Pnext) : 0.0);
        if (k == j) sP -= 0.5 * d_e[k], sd -= 0.5 * P_e[k];
        if (k == i) sP += 0.5 * d_e[k], sd += 0.5 * P_e[k];
        if (h <= 0) {
          var += sP * sP * sigma_P * sigma_P + sd * sd * sigma_d * sigma_d;
          continue;
        }
        const LocalWeights& lw = fit_weights[k - start];
        for (std::size_t q = 0; q < lw.weights.size(); ++q) {
          gP[lw.first_row + q] += sP * lw.weights[q];
          gd[lw.first_row + q] += sd * lw.weights[q];
        }
      }
      if (h > 0)
        for (int r = start; r < m; ++r) {
          var += gP[r] * gP[r] * sigma_P * sigma_P + gd[r] * gd[r] * sigma_d * sigma_d;
          gP[r] = gd[r] = 0.0;
        }
      const double rel_da = da_noise_factor(i, j) * sigma_a / da;
      const double u = std::sqrt(var / (B * da * B * da) + R * R * rel_da * rel_da);
      result.curve.crack_length.push_back(0.5 * (a_e[i] + a_e[j]));
      result.curve.R.push_back(R);
      result.curve.R_uncertainty.push_back(k_cov * u);
      result.crack_growth.push_back(0.5 * (a_e[i] + a_e[j]) - a0);
      result.load.push_back(w.P[j]);
      result.displacement.push_back(w.d[j]);
      result.rows.push_back(w.row[j]);
      last_end = j;
    }
    result.points_used = result.curve.size() > 0 ? last_end - start + 1 : 0;
    AddDropped(result, "tail without crack growth after the last increment",
               result.curve.size() > 0 ? m - 1 - last_end : m - start);
    if (result.curve.size() == 0)
      throw Error(ErrorKind::kInput, "no crack increment is resolvable against the crack-length noise",
                  {.file = p.src, .field = "crack_length", .value = Mm(w.a.back() - a0),
                   .expected = fmt::format(
                       "growth >= {} (R curve stage: energy method); way out: --min-increment "
                       "smaller, --crack-noise, or --method mbt|cc (DCB) / lefm (CT)",
                       Mm(da_min))});
    result.curve.initiation_R = result.curve.R.front();
  }
}

}  // namespace bridgefit::experiment::detail
