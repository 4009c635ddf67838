// Specimen outcomes as bytes (outcome_wire.hpp): a flat little format of
// fixed-size numbers (memcpy, so doubles arrive bit for bit), strings and
// vectors with a 64-bit count first.
#include "outcome_wire.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::campaign::wire {
namespace {

constexpr std::uint32_t kMagic = 0x31574642;  // "BFW1": change it when the layout changes

template <class T>
concept Plain = std::is_arithmetic_v<T> || std::is_enum_v<T>;

class Writer {
 public:
  template <Plain T>
  void Field(const T& v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void Field(const std::string& s) {
    Count(s.size());
    bytes_ += s;
  }
  void Field(const std::vector<double>& v) {
    Count(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  }
  template <std::size_t N>
  void Field(const std::array<double, N>& a) {
    for (double x : a) Field(x);
  }
  // A vector of structs, each through `each(io, item)`.
  template <class T, class F>
  void Items(const std::vector<T>& items, F&& each) {
    Count(items.size());
    for (const T& item : items) each(*this, item);
  }
  std::string Take() { return std::move(bytes_); }

 private:
  void Count(std::size_t n) { Field(static_cast<std::uint64_t>(n)); }
  std::string bytes_;
};

class Reader {
 public:
  Reader(const std::string& bytes, int from_rank) : bytes_(bytes), rank_(from_rank) {}
  template <Plain T>
  void Field(T& v) {
    std::memcpy(&v, Take(sizeof v), sizeof v);
  }
  void Field(std::string& s) {
    const std::uint64_t n = Count(1);
    s.assign(Take(n), n);
  }
  void Field(std::vector<double>& v) {
    const std::uint64_t n = Count(sizeof(double));
    v.resize(n);
    if (n) std::memcpy(v.data(), Take(n * sizeof(double)), n * sizeof(double));
  }
  template <std::size_t N>
  void Field(std::array<double, N>& a) {
    for (double& x : a) Field(x);
  }
  template <class T, class F>
  void Items(std::vector<T>& items, F&& each) {
    items.resize(Count(1));
    for (T& item : items) each(*this, item);
  }
  bool done() const { return offset_ == bytes_.size(); }
  [[noreturn]] void Corrupt() const {
    throw Error(ErrorKind::kRuntime, "a rank's campaign results do not decode",
                {.field = fmt::format("results from rank {}", rank_),
                 .value = fmt::format("{} bytes, stopped at byte {}", bytes_.size(), offset_),
                 .expected = "every rank running the same bridgefit build"});
  }

 private:
  // A count of items of at least `item_bytes` each that the rest can hold.
  std::uint64_t Count(std::uint64_t item_bytes) {
    std::uint64_t n = 0;
    Field(n);
    if (n > (bytes_.size() - offset_) / item_bytes) Corrupt();
    return n;
  }
  const char* Take(std::uint64_t n) {
    if (n > bytes_.size() - offset_) Corrupt();
    const char* at = bytes_.data() + offset_;
    offset_ += n;
    return at;
  }
  const std::string& bytes_;
  int rank_;
  std::size_t offset_ = 0;
};

// One function per type for both directions (Writer with const values,
// Reader filling them in), so the two cannot drift apart.
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
  io.Items(s.profiles, [](auto& io2, auto& p) { Visit(io2, p); });
  io.Field(s.fitted_crack_length), io.Field(s.fitted_R), io.Field(s.fitted_delta_root);
  io.Field(s.fitted_displacement), io.Field(s.fitted_record_load), io.Field(s.fitted_load);
  io.Field(s.best_parameters);
}
// A field added to these structs must be sent too (and kMagic changed): the
// sizes are x86-64 / libstdc++'s when this was written; other platforms skip
// the check.
#if defined(__x86_64__) && defined(__GLIBCXX__)
static_assert(sizeof(inverse::FitSummary) == 1240, "FitSummary changed: update Visit");
static_assert(sizeof(inverse::ParameterEstimate) == 168, "ParameterEstimate changed: update Visit");
static_assert(sizeof(inverse::FitData) == 160, "FitData changed: update Visit");
static_assert(sizeof(laws::LawShape) == 72, "LawShape changed: update Visit");
static_assert(sizeof(inverse::Profile) == 88 && sizeof(inverse::ProfilePoint) == 48 &&
                  sizeof(inverse::StartResult) == 96 && sizeof(laws::TruncationBounds) == 40,
              "a part of FitSummary changed: update Visit");
#endif

template <class Io, class D>
void Visit(Io& io, D& d) requires std::is_same_v<std::remove_const_t<D>, inverse::FitData> {
  io.Field(d.target), io.Field(d.crack_length), io.Field(d.R), io.Field(d.R_uncertainty);
  io.Field(d.kind), io.Field(d.displacement), io.Field(d.load), io.Field(d.load_uncertainty);
}

// The fit as the campaign uses it on rank 0.
template <class Io, class R>
void Visit(Io& io, R& run) requires std::is_same_v<std::remove_const_t<R>, pipeline::FitRun> {
  io.Field(run.r_kind);
  Visit(io, run.data);
  Visit(io, run.summary);
  io.Field(run.shape.family), io.Field(run.shape.peak_ratio), io.Field(run.shape.alpha);
  io.Field(run.shape.d_points), io.Field(run.shape.s_points);
  io.Field(run.resolution);
  io.Field(run.model_note);
}

}  // namespace

std::string EncodeOutcomes(const std::vector<SpecimenOutcome>& specimens,
                           const std::vector<std::size_t>& indices, const std::string& rank_error) {
  Writer out;
  out.Field(kMagic);
  out.Field(rank_error);
  if (!rank_error.empty()) return out.Take();
  out.Field(static_cast<std::uint64_t>(indices.size()));
  for (std::size_t i : indices) {
    const SpecimenOutcome& s = specimens.at(i);
    out.Field(static_cast<std::uint64_t>(i));
    out.Field(s.name), out.Field(s.error), out.Field(s.wall_s), out.Field(s.rank);
    out.Field(s.ran());
    if (!s.ran()) continue;
    const bool load = s.run->load_data.has_value();
    out.Field(load);
    if (load) Visit(out, *s.run->load_data);
    Visit(out, *s.run);
    out.Field(s.fit_file);
  }
  return out.Take();
}

void DecodeOutcomes(const std::string& bytes, int from_rank,
                    std::vector<SpecimenOutcome>& specimens) {
  Reader in(bytes, from_rank);
  std::uint32_t magic = 0;
  in.Field(magic);
  if (magic != kMagic) in.Corrupt();
  std::string rank_error;
  in.Field(rank_error);
  if (!rank_error.empty())
    throw Error(ErrorKind::kRuntime, fmt::format("rank {}: {}", from_rank, rank_error),
                {.field = "campaign results from another rank"});
  std::uint64_t count = 0;
  in.Field(count);
  for (std::uint64_t k = 0; k < count; ++k) {
    std::uint64_t i = 0;
    in.Field(i);
    if (i >= specimens.size()) in.Corrupt();
    SpecimenOutcome& s = specimens[i];
    std::string name;
    in.Field(name);
    if (name != s.name) in.Corrupt();  // the ranks read different manifests
    in.Field(s.error), in.Field(s.wall_s), in.Field(s.rank);
    bool ran = false;
    in.Field(ran);
    if (!ran) continue;
    pipeline::FitRun& run = s.run.emplace();
    bool load = false;
    in.Field(load);
    if (load) Visit(in, run.load_data.emplace());
    Visit(in, run);
    in.Field(s.fit_file);
  }
  if (!in.done()) in.Corrupt();
}

}  // namespace bridgefit::campaign::wire
