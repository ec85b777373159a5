#pragma once
/// \file
/// Wall-clock seconds for the reports' `timing_s` (steady clock: immune to clock changes).
#include <chrono>

namespace fvx {

class Stopwatch {
 public:
  /// Seconds since construction or the last restart().
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// seconds(), then starts again from now: the time of one stage after another.
  double lap() {
    const double s = seconds();
    start_ = Clock::now();
    return s;
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_ = Clock::now();
};

}  // namespace fvx
