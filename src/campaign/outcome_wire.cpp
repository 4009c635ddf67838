// Specimen outcomes as bytes (outcome_wire.hpp), written and read with
// parallel::ByteWriter / ByteReader (doubles bit for bit).
#include "outcome_wire.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/fit_wire.hpp"
#include "bridgefit/parallel/bytes.hpp"

namespace bridgefit::campaign::wire {
namespace {

constexpr std::uint32_t kMagic = 0x35574642;  // "BFW5": change it when the layout changes

using Writer = parallel::ByteWriter;
using Reader = parallel::ByteReader;
using inverse::wire::Visit;

// The fit as the campaign uses it on rank 0.
template <class Io, class R>
void Visit(Io& io, R& run) requires std::is_same_v<std::remove_const_t<R>, pipeline::FitRun> {
  io.Field(run.r_kind);
  Visit(io, run.data);
  Visit(io, run.summary);
  io.Field(run.shape.family), io.Field(run.shape.peak_ratio), io.Field(run.shape.alpha);
  io.Field(run.shape.d_points), io.Field(run.shape.s_points), io.Field(run.shape.interpolation);
  io.Field(run.resolution);
  io.Field(run.model_note);
  // A load record's nuisance parameters, where the joint fit starts them.
  io.Field(run.calibration.modulus_factor), io.Field(run.calibration.series_compliance);
}

// What a specimen's DIC gave: the frames' crack lengths (into the request,
// so another rank's fit of it reads the same record), the notes and, with
// the fit files, its dic file.
void WriteDic(Writer& out, const SpecimenOutcome& s, bool with_files) {
  const auto strings = [](Writer& io, const std::string& text) { io.Field(text); };
  out.Items(s.notes, strings);
  const auto& frames = s.request.frame_crack_lengths;
  out.Field(frames.has_value());
  if (frames) {
    out.Items(frames->image, strings);
    out.Field(frames->crack_length), out.Field(frames->source);
  }
  out.Field(with_files ? s.dic_file : std::string());
}

void ReadDic(Reader& in, SpecimenOutcome& s) {
  const auto strings = [](Reader& io, std::string& text) { io.Field(text); };
  in.Items(s.notes, strings);
  bool has_frames = false;
  in.Field(has_frames);
  if (has_frames) {
    auto& frames = s.request.frame_crack_lengths.emplace();
    in.Items(frames.image, strings);
    in.Field(frames.crack_length), in.Field(frames.source);
    if (frames.crack_length.size() != frames.image.size()) in.Corrupt();
  }
  in.Field(s.dic_file);
}

}  // namespace

std::string EncodeOutcomes(const std::vector<SpecimenOutcome>& specimens,
                           const std::vector<std::size_t>& indices, const std::string& rank_error,
                           bool with_fit_files) {
  Writer out;
  out.Field(kMagic);
  out.Field(rank_error);
  if (!rank_error.empty()) return out.Take();
  out.Field(static_cast<std::uint64_t>(indices.size()));
  for (std::size_t i : indices) {
    const SpecimenOutcome& s = specimens.at(i);
    out.Field(static_cast<std::uint64_t>(i));
    out.Field(s.name), out.Field(s.error), out.Field(s.wall_s), out.Field(s.rank);
    WriteDic(out, s, with_fit_files);
    out.Field(s.ran());
    if (!s.ran()) continue;
    const bool load = s.run->load_data.has_value();
    out.Field(load);
    if (load) Visit(out, *s.run->load_data);
    Visit(out, *s.run);
    out.Field(with_fit_files ? s.fit_file : std::string());
  }
  return out.Take();
}

void DecodeOutcomes(const std::string& bytes, int from_rank,
                    std::vector<SpecimenOutcome>& specimens) {
  Reader in(bytes, "campaign results", from_rank);
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
    ReadDic(in, s);
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
