#pragma once
// The fit's value types as bytes between the ranks of one job (issue 20):
// Visit(io, value) with a parallel::ByteWriter (const values) or a
// parallel::ByteReader (filling them in), one function per type for both
// directions so the two cannot drift apart. Doubles travel bit for bit.

#include <type_traits>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::inverse::wire {

template <class Io, class E>
void Visit(Io& io,
           E& e) requires std::is_same_v<std::remove_const_t<E>, inverse::ParameterEstimate> {
  io.Field(e.value), io.Field(e.ci95_low), io.Field(e.ci95_high), io.Field(e.lower_bound);
  io.Field(e.identified), io.Field(e.fixed), io.Field(e.decided_by), io.Field(e.note);
  io.Field(e.interval_status), io.Field(e.interval_reason);
  io.Field(e.statistical_ci95_low), io.Field(e.statistical_ci95_high), io.Field(e.model_bias);
}

template <class Io, class P>
void Visit(Io& io, P& p) requires std::is_same_v<std::remove_const_t<P>, inverse::Profile> {
  io.Field(p.parameter);
  io.Items(p.points, [](auto& io2, auto& q) {
    io2.Field(q.value), io2.Field(q.chi2), io2.Field(q.ok), io2.Field(q.parameters);
  });
  io.Field(p.chi2_threshold), io.Field(p.flat), io.Field(p.status), io.Field(p.status_reason);
  io.Field(p.resolves);
}

template <class Io, class S>
void Visit(Io& io, S& s) requires std::is_same_v<std::remove_const_t<S>, inverse::FitSummary> {
  io.Field(s.model), io.Field(s.optimizer), io.Field(s.law), io.Field(s.evaluations);
  io.Field(s.failed_evaluations), io.Field(s.wall_s), io.Field(s.converged);
  io.Field(s.stop_reason), io.Field(s.steady_state_reached), io.Field(s.steady_state_crack_length);
  io.Field(s.target), io.Field(s.rms_residual), io.Field(s.chi2), io.Field(s.reduced_chi2);
  io.Field(s.residual_autocorrelation), io.Field(s.interval_inflation), io.Field(s.noise_scale2);
  io.Field(s.data_points), io.Field(s.bridging_detected), io.Field(s.verdict);
  Visit(io, s.sigma_c), Visit(io, s.J_B), Visit(io, s.delta_c), Visit(io, s.J_tip_c);
  io.Field(s.bounds.J_B_lower), io.Field(s.bounds.delta_c_lower), io.Field(s.bounds.R_max);
  io.Field(s.bounds.J_tip_c), io.Field(s.bounds.crack_length_max);
  io.Items(s.starts, [](auto& io2, auto& r) {
    io2.Field(r.start), io2.Field(r.end), io2.Field(r.cost), io2.Field(r.evaluations);
    io2.Field(r.stop_reason);
  });
  io.Field(s.outlier_crack_lengths), io.Field(s.outlier_R);
  io.Field(s.misfit.points), io.Field(s.misfit.crack_length_from), io.Field(s.misfit.crack_length_to);
  io.Field(s.misfit.largest_sd), io.Field(s.misfit.side);
  io.Items(s.profiles, [](auto& io2, auto& p) { Visit(io2, p); });
  io.Field(s.fitted_crack_length), io.Field(s.fitted_R), io.Field(s.fitted_delta_root);
  io.Field(s.fitted_displacement), io.Field(s.fitted_record_load), io.Field(s.fitted_load);
  io.Field(s.best_parameters);
}
// A field added to these structs must be sent too (and the magic numbers of the
// messages that carry them changed: campaign/outcome_wire.cpp): the
// sizes are x86-64 / libstdc++'s when this was written; other platforms skip
// the check.
#if defined(__x86_64__) && defined(__GLIBCXX__)
static_assert(sizeof(inverse::FitSummary) == 1280, "FitSummary changed: update Visit");
static_assert(sizeof(inverse::ParameterEstimate) == 168, "ParameterEstimate changed: update Visit");
static_assert(sizeof(inverse::FitData) == 160, "FitData changed: update Visit");
static_assert(sizeof(laws::LawShape) == 80, "LawShape changed: update Visit");
static_assert(sizeof(inverse::Profile) == 88 && sizeof(inverse::ProfilePoint) == 48 &&
                  sizeof(inverse::StartResult) == 96 && sizeof(laws::TruncationBounds) == 40 &&
                  sizeof(inverse::MisfitRun) == 40,
              "a part of FitSummary changed: update Visit");
#endif

template <class Io, class D>
void Visit(Io& io, D& d) requires std::is_same_v<std::remove_const_t<D>, inverse::FitData> {
  io.Field(d.target), io.Field(d.crack_length), io.Field(d.R), io.Field(d.R_uncertainty);
  io.Field(d.kind), io.Field(d.displacement), io.Field(d.load), io.Field(d.load_uncertainty);
}

}  // namespace bridgefit::inverse::wire
