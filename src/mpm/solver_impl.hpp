// Private: the MPM solver state (SoA particles, grid, crack) shared by
// solver.cpp (options, public API, Run), solver_setup.cpp (construction,
// loading ramp, crack geometry), solver_stages.cpp (the explicit step as
// named stages) and solver_outputs.cpp (energies, J, COD, samples, fields).
#pragma once

#include "bridgefit/mpm/solver.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <type_traits>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "shape.hpp"

namespace bridgefit::mpm {

namespace solver_internal {

using Clock = std::chrono::steady_clock;
using Weights = detail::Weights;

inline double Orient(double ax, double ay, double bx, double by, double cx, double cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

}  // namespace solver_internal

using solver_internal::Clock;
using solver_internal::Orient;
using solver_internal::Weights;

struct Solver::Impl {
  Model model;
  SolverOptions opt;
  int threads = 1;

  // Grid.
  double h = 0, inv_h = 0, x0 = 0, y0 = 0;
  int nx = 0, ny = 0;
  std::size_t N = 0;
  std::vector<double> gm, gpx, gpy, gfx, gfy, gqx, gqy;  // 2 fields x N
  // Node velocities for the gather: v = p*/m, dv = (p* - p)/m (0 on empty nodes).
  std::vector<double> gvx, gvy, gdvx, gdvy;
  std::vector<int> node_constraint;                       // -1 or constraint index

  struct Band {
    int row0 = 0, rows = 0;
    std::vector<double> m, px, py, fx, fy;
  };
  std::vector<Band> bands;
  std::vector<std::size_t> chunk;  // thread t owns particles [chunk[t], chunk[t+1])

  // Particles (SoA).
  std::size_t P = 0;
  double lp = 0;      // half size in cell units (uGIMP)
  double inv_lp = 0;  // 1 / lp
  std::vector<double> px, py, vx, vy, mass, vol, sxx, syy, sxy, hxx, hxy, hyx, hyy, ux, uy,
      w, dexx, deyy, dgxy;
  std::vector<std::uint16_t> mask;

  // Crack (SoA over crack points).
  std::vector<double> cx, cy, uax, uay, ubx, uby, ctraction;
  double crack_xmin = 0, crack_xmax = 0, crack_ymin = 0, crack_ymax = 0;
  std::vector<std::int8_t> node_above;  // 1 above, 0 below (left of the crack direction)
  // Crack segments by cell column (segments within two columns), so the
  // crossing tests look at a handful of segments, not the whole crack.
  std::vector<std::vector<int>> segment_bucket;

  // State.
  double t = 0, dt = 0, alpha = 0, omega1 = 0, ramp_time = 0, max_time = 0;
  long step = 0;
  RunStatus status = RunStatus::kOk;
  std::string message = "not started";
  double external_work = 0, initial_energy = 0, energy_floor = 0;
  double kinetic = 0, strain = 0;
  double reaction_load = 0;  // per unit thickness
  double max_ke_se = 0;
  std::vector<HistorySample> history;
  FieldsCallback fields_callback;
  double stage_time[8] = {0};
  const char* stage_names[8] = {"particles_to_grid", "grid_update", "grid_to_particles",
                                "stress_update", "crack", "energies_and_checks", "J_integral",
                                "output"};

  // Nodes with less mass than this are left out (v = 0).
  double MassFloor() const { return 1e-9 * model.density * h * h; }

  // ---- construction, loading ramp and crack geometry (solver_setup.cpp)
  Impl(Model m, SolverOptions o);
  double Rate(double time) const;
  double Displacement(double time) const;
  void UpdateCrackGeometry();

  // ---- the explicit step as named stages (solver_stages.cpp)
  template <bool kGimp, bool mass_momentum, bool force>
  void ParticlesToGrid();
  void ConstrainVelocities(double rate);
  std::array<double, 2> ApplyConstraint(const NodeConstraint& c, int n, double m, double rate,
                                        double& qx, double& qy) const;
  void GridUpdate();
  void NodeVelocities(bool old);
  void Contact();
  double CodNormalAt(std::size_t k) const;
  double CodTangentialAt(std::size_t k) const;
  double CodNormalAtProjection(std::size_t seg, double x, double y) const;
  template <bool kGimp>
  bool GridToParticles(bool kinematics, bool gradient, double dt_frac, double* ke_out);
  double StressUpdate();
  void MoveCrack();
  template <bool kGimp>
  bool StepImpl();
  bool Step();

  // ---- energies, J, COD, samples and fields (solver_outputs.cpp)
  double StrainEnergyPerThickness() const;
  void Fail(const std::string& why);
  JResult ComputeJ(int k) const;
  double CodAt(double x) const;
  HistorySample Sample() const;
  ParticleFields Fields() const;

  // ---- crack crossing tests, inline: called per particle in the hot loops

  std::size_t NearestSegment(double x, double y) const {
    const int column = static_cast<int>(std::floor((x - x0) * inv_h));
    const std::vector<int>* bucket =
        column >= 0 && column < nx && !segment_bucket[column].empty() ? &segment_bucket[column]
                                                                      : nullptr;
    std::size_t best = 0;
    double best_d = 1e300;
    const std::size_t count = bucket ? bucket->size() : cx.size() - 1;
    for (std::size_t q = 0; q < count; ++q) {
      const std::size_t k = bucket ? static_cast<std::size_t>((*bucket)[q]) : q;
      const double ax = cx[k], ay = cy[k], bx = cx[k + 1], by = cy[k + 1];
      const double dx = bx - ax, dy = by - ay;
      const double len2 = dx * dx + dy * dy;
      double s = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0.0;
      s = std::clamp(s, 0.0, 1.0);
      const double ex = ax + s * dx - x, ey = ay + s * dy - y;
      const double d = ex * ex + ey * ey;
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    return best;
  }

  // Bit k of the mask: the line from the particle to node k of its patch
  // crosses the crack (the node then takes the particle into field 1).
  std::uint16_t CrackMask(double x, double y, const Weights& wt) const {
    if (cx.empty()) return 0;
    const double reach = (1.0 + lp) * h + 1e-12;
    if (x < crack_xmin - reach - h || x > crack_xmax + reach + h || y < crack_ymin - reach - h ||
        y > crack_ymax + reach + h)
      return 0;
    // Candidate segments overlapping the patch's box.
    const double bx0 = x0 + wt.i0 * h, bx1 = bx0 + 2 * h;
    const double by0 = y0 + wt.j0 * h, by1 = by0 + 2 * h;
    const int column = static_cast<int>(std::floor((x - x0) * inv_h));
    if (column < 0 || column >= nx) return 0;
    std::size_t cand[16];
    int nc = 0;
    for (int kk : segment_bucket[column]) {
      if (nc == 16) break;
      const std::size_t k = static_cast<std::size_t>(kk);
      const double sx0 = std::min(cx[k], cx[k + 1]), sx1 = std::max(cx[k], cx[k + 1]);
      const double sy0 = std::min(cy[k], cy[k + 1]), sy1 = std::max(cy[k], cy[k + 1]);
      if (sx1 < std::min(bx0, x) || sx0 > std::max(bx1, x) || sy1 < std::min(by0, y) ||
          sy0 > std::max(by1, y))
        continue;
      cand[nc++] = k;
    }
    if (nc == 0) return 0;
    std::uint16_t bits = 0;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const double nxp = x0 + (wt.i0 + a) * h, nyp = y0 + (wt.j0 + b) * h;
        for (int q = 0; q < nc; ++q) {
          const std::size_t k = cand[q];
          const double o1 = Orient(cx[k], cy[k], cx[k + 1], cy[k + 1], x, y);
          const double o2 = Orient(cx[k], cy[k], cx[k + 1], cy[k + 1], nxp, nyp);
          if (!((o1 < 0.0) != (o2 < 0.0)) || o1 == 0.0 || o2 == 0.0) continue;
          // Endpoints on the particle-node line count as on its positive side,
          // so a line through a joint crosses exactly one of the two segments.
          const double o3 = Orient(x, y, nxp, nyp, cx[k], cy[k]);
          const double o4 = Orient(x, y, nxp, nyp, cx[k + 1], cy[k + 1]);
          if ((o3 < 0.0) != (o4 < 0.0)) {
            bits |= static_cast<std::uint16_t>(1u << (b * 3 + a));
            break;
          }
        }
      }
    return bits;
  }

  template <bool kGimp>
  inline void ComputeWeights(double x, double y, Weights& wt) const {
    detail::PatchWeights<kGimp>(x, y, x0, y0, inv_h, lp, inv_lp, wt);
  }
};

}  // namespace bridgefit::mpm
