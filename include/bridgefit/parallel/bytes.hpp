#pragma once
// Values as bytes between the ranks of one job (issue 20): fixed-size
// numbers copied as they are (doubles arrive bit for bit), strings and
// vectors with a 64-bit count first. The ranks run one build on machines of
// one byte order (a cluster); a message that does not decode throws Error
// (kRuntime) naming what it held and the rank that sent it.

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "bridgefit/core/error.hpp"

namespace bridgefit::parallel {

template <class T>
concept PlainBytes = std::is_arithmetic_v<T> || std::is_enum_v<T>;

class ByteWriter {
 public:
  template <PlainBytes T>
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
  // A vector of items, each through `each(io, item)`.
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

class ByteReader {
 public:
  // `what`: what the message holds, for the error ("campaign results").
  ByteReader(const std::string& bytes, std::string what, int from_rank)
      : bytes_(bytes), what_(std::move(what)), rank_(from_rank) {}
  template <PlainBytes T>
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
  int from_rank() const { return rank_; }
  [[noreturn]] void Corrupt() const {
    throw Error(ErrorKind::kRuntime, "a rank's " + what_ + " do not decode",
                {.field = what_ + " from rank " + std::to_string(rank_),
                 .value = std::to_string(bytes_.size()) + " bytes, stopped at byte " +
                          std::to_string(offset_),
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
  std::string what_;
  int rank_;
  std::size_t offset_ = 0;
};

}  // namespace bridgefit::parallel
