#pragma once
// Explicit 2D material point method with an explicit crack (two velocity
// fields on cracked nodes, frictionless contact), quasi-static loading by a
// prescribed velocity ramp with damping, and the J integral on grid contours.
//
// One step (stage, equation):
//   ParticlesToGrid   m_i = sum S_ip m_p, p_i = sum S_ip m_p v_p,
//                     f_i = -sum V_p sigma_p . grad S_ip          (per field)
//   GridUpdate        p_i* = p_i + dt (f_i - alpha p_i), contact, constraints
//   GridToParticles   v_p += sum S_ip (p_i* - p_i)/m_i, x_p += dt sum S_ip p_i*/m_i
//   StressUpdate      sigma_p += C : sym(sum v_i (x) grad S_ip) dt
// USF updates stresses with the velocities before the force update, USL
// after it, USAVG half and half.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/mpm/model.hpp"

namespace bridgefit::mpm {

enum class ShapeFunction { kGimp, kLinear };
enum class UpdateScheme { kUSF, kUSL, kUSAVG };
const char* ShapeFunctionName(ShapeFunction shape);
const char* UpdateSchemeName(UpdateScheme scheme);

struct SolverOptions {
  ShapeFunction shape = ShapeFunction::kGimp;
  UpdateScheme scheme = UpdateScheme::kUSL;
  // dt = cfl_factor h / c_max (uGIMP with ppc > 2: times sqrt(2/ppc))
  double cfl_factor = 0.5;
  int threads = 0;          // 0: OpenMP default

  // Loading: the load-point displacement rises from 0 to target_displacement
  // [m] over ramp_time with rate (D/T)(1 - cos 2 pi t/T), then holds.
  double target_displacement = 0.0;
  double ramp_time = 0.0;       // [s]; 0: ramp_periods / f_1
  double ramp_periods = 2.0;    // ramp length in lowest-mode periods (auto ramp)
  // Stationary run end: after the ramp, stop once KE < settle_ratio SE
  // (checked over one lowest-mode period), or at max_time.
  double settle_ratio = 1e-7;
  double max_time = 0.0;        // [s]; 0: ramp + 12 lowest-mode periods
  long max_steps = 0;           // 0: no limit

  // Damping: constant grid damping alpha [1/s] (a = f/m - alpha v); < 0: auto
  // = damping_ratio * 2 omega_1. Feedback damping adjusts alpha so that
  // KE/SE tends to kinetic_target (d alpha/dt = gain omega_1^2 (KE/SE/target - 1)).
  double damping = -1.0;
  double damping_ratio = 1.0;
  // Particle damping [1/s]: v_p -= dt beta v_p in the gather; it also damps
  // particle-velocity modes the grid does not see (FLIP noise). < 0: equal
  // to the grid damping alpha.
  double particle_damping = 0.0;
  bool feedback_damping = false;
  double kinetic_target = 1e-3;
  double feedback_gain = 0.5;

  bool contact = true;   // frictionless crack-face contact
  // Unstable when KE + SE > energy_growth_limit (initial energy + external work).
  double energy_growth_limit = 2.0;

  int history_every = 20;              // steps between history samples
  std::vector<int> contour_cells = {3, 5};  // J contour half sizes [cells]
  int fields_every = 0;                // particle-field callback every N steps
  bool progress = false;               // progress line on stderr

  bool IsValid(std::string* why) const;
};

struct HistorySample {
  double time = 0.0;           // [s]
  long step = 0;
  double load = 0.0;           // [N] (thickness included)
  double displacement = 0.0;   // prescribed load-point displacement [m]
  double load_line_cod = 0.0;  // crack opening at x = 0 (CT load line) [m]
  double kinetic = 0.0;        // [J]
  double strain = 0.0;         // [J]
  double external_work = 0.0;  // [J]
  double damping = 0.0;        // alpha [1/s]
  std::vector<double> J;       // per contour in options.contour_cells [J/m^2]
  std::vector<double> J_tip;   // J minus the crack-face traction term
};

// J on one contour: the contour integral, the crack-face traction term
// (sum of sigma d(delta) between the contour's crossing and the tip) and
// J_tip = J - face term (PHYSICS section 4).
struct JResult {
  int half_cells = 0;
  double J = 0.0;
  double face_term = 0.0;
  double J_tip = 0.0;
};

struct CrackPointState {
  double x = 0.0, y = 0.0;              // current mid position
  double ux_above = 0.0, uy_above = 0.0;  // face displacements
  double ux_below = 0.0, uy_below = 0.0;
  double cod_normal = 0.0;      // opening along the crack normal
  double cod_tangential = 0.0;  // sliding
  double traction = 0.0;        // closing normal traction [Pa] (bridging, part 2)
};

struct ParticleFields {
  std::vector<double> x, y, ux, uy, vx, vy, sxx, syy, sxy, strain_energy_density;
};

struct Summary {
  RunStatus status = RunStatus::kOk;
  std::string message;
  long steps = 0;
  std::size_t particles = 0;
  std::size_t nodes = 0;
  double dt = 0.0;
  double time = 0.0;
  double wall_s = 0.0;
  double particle_steps_per_s = 0.0;
  int threads = 1;
  double max_kinetic_to_strain = 0.0;  // after the first 10% of the ramp
  double final_load = 0.0;
  double final_displacement = 0.0;
  double final_load_line_cod = 0.0;
  std::vector<JResult> final_J;
  std::vector<HistorySample> history;
  std::vector<std::pair<std::string, double>> stage_seconds;  // profile

  std::string BriefReport() const;
};

class Solver {
 public:
  // Throws Error(kInput) when the model or options are invalid.
  Solver(Model model, SolverOptions options);
  ~Solver();
  Solver(const Solver&) = delete;
  Solver& operator=(const Solver&) = delete;

  // Runs the loading programme to its end (or to instability).
  Summary Run();
  // One step; false once the run is unstable (see status()).
  bool Step();

  using FieldsCallback = std::function<void(long step, double time, const ParticleFields&)>;
  void SetFieldsCallback(FieldsCallback callback);

  RunStatus status() const;
  const std::string& message() const;
  double time() const;
  double dt() const;
  long steps() const;
  const Model& model() const;
  const SolverOptions& options() const;

  ParticleFields Fields() const;
  std::vector<CrackPointState> CrackPoints() const;
  // Sets the closing traction of crack point k (for the face term of J;
  // forces on the faces come with part 2).
  void SetCrackTraction(std::size_t k, double traction);
  // Normal opening at x along the crack (linear between crack points).
  double CodAt(double x) const;
  JResult ComputeJ(int half_cells) const;
  HistorySample Sample() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bridgefit::mpm
