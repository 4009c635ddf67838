#pragma once
// Progress on stderr for long runs. Never writes to stdout, so `--json`
// output stays one clean object. Silent for runs shorter than `delay_s`.

#include <chrono>
#include <cstddef>
#include <string>

namespace bridgefit {

class Progress {
 public:
  // `total` = number of work units (0 when unknown).
  Progress(std::string label, std::size_t total, bool enabled = true,
           double delay_s = 1.0);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Reports that `done` units are finished; redraws at most ~5 times a second.
  void Update(std::size_t done);
  // Ends the line (prints the elapsed time if anything was shown).
  void Finish();
  double ElapsedSeconds() const;

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  double delay_s_;
  bool shown_ = false;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

// Wall-clock stopwatch for Summary::wall_s fields.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace bridgefit
