#pragma once
// Independent items of work dealt over the ranks of a job (issue 20): item j
// runs on Communicator::OwnerOf(j) (j mod N, so the assignment depends only
// on N) and every rank receives every item, doubles bit for bit. Used by a
// fit's starts and profiles (src/inverse/fit_ranks.cpp) and the design's
// forward runs (src/campaign/design.cpp).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bridgefit/parallel/bytes.hpp"
#include "bridgefit/parallel/communicator.hpp"

namespace bridgefit::parallel {

// Items 0..count-1 dealt over the ranks: each rank's own items, written by
// `write(j, out)`, go to every rank, where `read(j, in)` reads them back; a
// message with another magic, or an item its sender does not own, is corrupt
// (ByteReader::Corrupt). Collective: every rank calls it with the same count
// and magic. `what` names the message for the error ("fit profiles").
template <class Write, class Read>
void ShareOwned(Communicator& ranks, std::size_t count, std::uint32_t magic, const char* what,
                Write&& write, Read&& read) {
  ByteWriter out;
  out.Field(magic);
  for (std::size_t j = 0; j < count; ++j) {
    if (ranks.OwnerOf(j) != ranks.rank()) continue;
    out.Field(static_cast<std::uint64_t>(j));
    write(j, out);
  }
  const std::vector<std::string> messages = ranks.AllGather(out.Take());
  for (int from = 0; from < static_cast<int>(messages.size()); ++from) {
    if (from == ranks.rank()) continue;
    ByteReader in(messages[from], what, from);
    std::uint32_t their_magic = 0;
    in.Field(their_magic);
    if (their_magic != magic) in.Corrupt();
    while (!in.done()) {
      std::uint64_t j = 0;
      in.Field(j);
      if (j >= count || ranks.OwnerOf(j) != from) in.Corrupt();
      read(static_cast<std::size_t>(j), in);
    }
  }
}

}  // namespace bridgefit::parallel
