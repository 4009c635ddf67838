// A fit's profiles dealt over the ranks of a job (FitOptions::ranks, issue
// 20): the ranks check that they start from the same optimum, each runs the
// profiles it owns, and every rank receives every profile, doubles bit for
// bit, so each continues as the fit on one process would.
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/fit_wire.hpp"
#include "bridgefit/parallel/bytes.hpp"
#include "bridgefit/parallel/communicator.hpp"
#include "bridgefit/parallel/share_owned.hpp"
#include "fit_impl.hpp"

namespace bridgefit::inverse::fit_internal {
namespace {

constexpr std::uint32_t kProfilesMagic = 0x31504642;  // "BFP1": change them when the layout changes
constexpr std::uint32_t kStartsMagic = 0x31534642;    // "BFS1"

template <class Io, class E>
void VisitEdge(Io& io, E& e) {
  io.Field(e.x), io.Field(e.status), io.Field(e.reason);
}

template <class Io, class L>
void VisitLocal(Io& io, L& r) {
  io.Field(r.x), io.Field(r.chi2), io.Field(r.evaluations), io.Field(r.stop_reason);
  io.Field(r.converged);
}

}  // namespace

void CheckSameOptimum(parallel::Communicator& ranks, const LocalResult& best,
                      const std::vector<double>& full, double threshold) {
  parallel::ByteWriter own;
  own.Field(best.x), own.Field(best.chi2), own.Field(full), own.Field(threshold);
  const std::string mine = own.Take();
  const std::string root = ranks.Broadcast(mine);
  if (root != mine)
    throw Error(ErrorKind::kInternal,
                fmt::format("rank {} reached another optimum than rank 0 before the profiles "
                            "(chi^2 {:.17g}); the ranks' fits would not fit together",
                            ranks.rank(), best.chi2),
                {.field = "fit over MPI ranks",
                 .expected = "every rank running the same build on the same inputs"});
}

void ShareProfileRuns(parallel::Communicator& ranks, std::vector<ProfileRun>& runs) {
  parallel::ShareOwned(
      ranks, runs.size(), kProfilesMagic, "fit profiles",
      [&](std::size_t q, parallel::ByteWriter& out) {
        const ProfileRun& run = runs[q];
        out.Field(run.k), out.Field(run.evaluations), out.Field(run.failures);
        wire::Visit(out, run.profile);
        VisitEdge(out, run.low), VisitEdge(out, run.high);
      },
      [&](std::size_t q, parallel::ByteReader& in) {
        ProfileRun& run = runs[q];
        in.Field(run.k), in.Field(run.evaluations), in.Field(run.failures);
        wire::Visit(in, run.profile);
        VisitEdge(in, run.low), VisitEdge(in, run.high);
      });
}

void ShareStartRuns(parallel::Communicator& ranks, std::vector<StartRun>& runs,
                    const Objective& objective) {
  std::vector<bool> remote(runs.size(), false);
  parallel::ShareOwned(
      ranks, runs.size(), kStartsMagic, "fit starts",
      [&](std::size_t k, parallel::ByteWriter& out) {
        const StartRun& run = runs[k];
        VisitLocal(out, run.result);
        out.Field(run.evaluations), out.Field(run.failures), out.Field(run.last_failure);
      },
      [&](std::size_t k, parallel::ByteReader& in) {
        StartRun& run = runs[k];
        VisitLocal(in, run.result);
        in.Field(run.evaluations), in.Field(run.failures), in.Field(run.last_failure);
        remote[k] = true;
      });
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (remote[k]) objective.AddCounts(runs[k].evaluations, runs[k].failures);
  // The last failure a process alone would keep: the last start's that failed.
  for (std::size_t k = runs.size(); k-- > 0;)
    if (runs[k].failures > 0) {
      objective.SetLastFailure(runs[k].last_failure);
      break;
    }
}

}  // namespace bridgefit::inverse::fit_internal
