#pragma once
// Wall-clock timing for the benchmarks: a monotonic clock and the time since a start.

#include <chrono>

namespace medspheres::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

}  // namespace medspheres::bench
