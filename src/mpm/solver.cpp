#include "bridgefit/mpm/solver.hpp"

#include <chrono>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "solver_impl.hpp"

namespace bridgefit::mpm {

const char* ShapeFunctionName(ShapeFunction shape) {
  return shape == ShapeFunction::kGimp ? "uGIMP" : "linear";
}
const char* UpdateSchemeName(UpdateScheme scheme) {
  switch (scheme) {
    case UpdateScheme::kUSF: return "USF";
    case UpdateScheme::kUSL: return "USL";
    case UpdateScheme::kUSAVG: return "USAVG";
  }
  return "?";
}

bool SolverOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(cfl_factor > 0.0 && cfl_factor <= 10.0)) return fail("cfl_factor must be in (0, 10]");
  if (threads < 0) return fail("threads must be >= 0");
  if (!(target_displacement >= 0.0 || target_displacement < 0.0))
    return fail("target_displacement must be finite");
  if (!(ramp_time >= 0.0) || !(ramp_periods > 0.0)) return fail("ramp time must be positive");
  if (!(settle_ratio >= 0.0)) return fail("settle_ratio must be >= 0");
  if (!(max_time >= 0.0) || max_steps < 0) return fail("max_time/max_steps must be >= 0");
  if (!(damping_ratio >= 0.0)) return fail("damping_ratio must be >= 0");
  if (feedback_damping && !(kinetic_target > 0.0 && feedback_gain > 0.0))
    return fail("feedback damping needs kinetic_target > 0 and feedback_gain > 0");
  if (!(energy_growth_limit > 1.0)) return fail("energy_growth_limit must be > 1");
  if (history_every < 1) return fail("history_every must be >= 1");
  for (int k : contour_cells)
    if (k < 1) return fail("contour half sizes must be >= 1 cell");
  if (fields_every < 0) return fail("fields_every must be >= 0");
  return true;
}

std::string Summary::BriefReport() const {
  std::string s = fmt::format(
      "MPM {}: {} ({} steps of {:.3g} s, t = {:.4g} s, {} particles, {} nodes, {} threads, "
      "{:.3g} s wall, {:.3g} M particle-steps/s); P = {:.5g} N at {:.5g} mm; max KE/SE {:.3g}",
      RunStatusName(status), message, steps, dt, time, particles, nodes, threads, wall_s,
      particle_steps_per_s * 1e-6, final_load, final_displacement * 1e3, max_kinetic_to_strain);
  for (const auto& j : final_J)
    s += fmt::format("; J({} cells) = {:.5g} J/m^2", j.half_cells, j.J);
  return s;
}

Solver::Solver(Model model, SolverOptions options)
    : impl_(std::make_unique<Impl>(std::move(model), std::move(options))) {}
Solver::~Solver() = default;

bool Solver::Step() { return impl_->Step(); }
void Solver::SetFieldsCallback(FieldsCallback callback) {
  impl_->fields_callback = std::move(callback);
}
RunStatus Solver::status() const { return impl_->status; }
const std::string& Solver::message() const { return impl_->message; }
double Solver::time() const { return impl_->t; }
double Solver::dt() const { return impl_->dt; }
long Solver::steps() const { return impl_->step; }
const Model& Solver::model() const { return impl_->model; }
const SolverOptions& Solver::options() const { return impl_->opt; }
ParticleFields Solver::Fields() const { return impl_->Fields(); }
double Solver::CodAt(double x) const { return impl_->CodAt(x); }
JResult Solver::ComputeJ(int half_cells) const { return impl_->ComputeJ(half_cells); }
HistorySample Solver::Sample() const { return impl_->Sample(); }

void Solver::SetCrackTraction(std::size_t k, double traction) {
  BF_CHECK_INPUT(k < impl_->ctraction.size(), "crack point index out of range");
  impl_->ctraction[k] = traction;
}

std::vector<CrackPointState> Solver::CrackPoints() const {
  const Impl& m = *impl_;
  std::vector<CrackPointState> out(m.cx.size());
  for (std::size_t k = 0; k < m.cx.size(); ++k) {
    auto& c = out[k];
    c.x = m.cx[k];
    c.y = m.cy[k];
    c.ux_above = m.uax[k];
    c.uy_above = m.uay[k];
    c.ux_below = m.ubx[k];
    c.uy_below = m.uby[k];
    c.cod_normal = m.CodNormalAt(k);
    c.cod_tangential = m.CodTangentialAt(k);
    c.traction = m.ctraction[k];
  }
  return out;
}

Summary Solver::Run() {
  Impl& m = *impl_;
  Stopwatch watch;
  Summary s;
  s.particles = m.P;
  s.nodes = m.N;
  s.threads = m.threads;
  s.dt = m.dt;
  const long start_step = m.step;
  const double period = m.omega1 > 0.0 ? 2.0 * M_PI / m.omega1 : 0.0;
  const long window = period > 0.0 ? std::max(1L, static_cast<long>(period / m.dt)) : 0;
  double window_max = 0.0;
  long window_start = m.step;
  bool settled = false;
  const long estimate = static_cast<long>(m.max_time / m.dt) + 1;
  Progress progress("MPM", static_cast<std::size_t>(estimate), m.opt.progress);
  auto record = [&]() {
    const auto tick = Clock::now();
    m.history.push_back(m.Sample());
    m.stage_time[6] += std::chrono::duration<double>(Clock::now() - tick).count();
  };
  auto fields = [&]() {
    if (!m.fields_callback) return;
    const auto tick = Clock::now();
    m.fields_callback(m.step, m.t, m.Fields());
    m.stage_time[7] += std::chrono::duration<double>(Clock::now() - tick).count();
  };
  if (m.step == 0) {
    record();
    if (m.opt.fields_every > 0) fields();
  }
  while (true) {
    if (!m.Step()) break;
    if (m.step % m.opt.history_every == 0) record();
    if (m.opt.fields_every > 0 && m.step % m.opt.fields_every == 0) fields();
    progress.Update(static_cast<std::size_t>(m.step));
    if (m.t >= m.ramp_time && m.opt.settle_ratio > 0.0 && window > 0) {
      window_max = std::max(window_max, m.strain > 0.0 ? m.kinetic / m.strain : 1.0);
      if (m.step - window_start >= window) {
        if (window_max < m.opt.settle_ratio) {
          settled = true;
          break;
        }
        window_max = 0.0;
        window_start = m.step;
      }
    } else {
      window_start = m.step;
    }
    if (m.t >= m.max_time) break;
    if (m.opt.max_steps > 0 && m.step - start_step >= m.opt.max_steps) break;
  }
  progress.Finish();
  // The last state is recorded also when the run stopped unstable (for the
  // diagnosis; its numbers may be non-finite).
  if (m.history.empty() || m.history.back().step != m.step) record();
  if (m.status == RunStatus::kOk) {
    if (m.opt.fields_every > 0 && m.step % m.opt.fields_every != 0) fields();
    if (settled) {
      m.message = fmt::format("settled: KE/SE < {:g} over one lowest-mode period",
                              m.opt.settle_ratio);
    } else if (m.opt.settle_ratio > 0.0 && window > 0) {
      m.status = RunStatus::kNotConverged;
      m.message = fmt::format("not settled by t = {:.4g} s (last KE/SE window max {:.3g})", m.t,
                              window_max);
    } else {
      m.message = "reached the end time";
    }
  }
  s.status = m.status;
  s.message = m.message;
  s.steps = m.step;
  s.time = m.t;
  s.wall_s = watch.Seconds();
  s.particle_steps_per_s =
      s.wall_s > 0.0 ? static_cast<double>(m.P) * (m.step - start_step) / s.wall_s : 0.0;
  s.max_kinetic_to_strain = m.max_ke_se;
  s.final_load = m.reaction_load * m.model.thickness;
  s.final_displacement = m.Displacement(m.t);
  s.final_load_line_cod = m.CodAt(0.0);
  for (int k : m.opt.contour_cells) s.final_J.push_back(m.ComputeJ(k));
  s.history = m.history;
  for (int st = 0; st < 8; ++st) s.stage_seconds.emplace_back(m.stage_names[st], m.stage_time[st]);
  return s;
}

}  // namespace bridgefit::mpm
