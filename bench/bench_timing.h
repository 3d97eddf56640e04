#pragma once
// Timing for the benchmarks: a monotonic clock and the time since a start; the CPU time
// of the process.

#include <sys/resource.h>
#include <time.h>

#include <chrono>

namespace medspheres::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

// CPU seconds (user + system, every thread) of this process and its reaped children so far.
inline double cpu_seconds() {
  double total = 0.0;
  for (int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage u{};
    getrusage(who, &u);
    total += static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  return total;
}

}  // namespace medspheres::bench

namespace medspheres::bench {

// CPU microseconds of the calling thread so far: time it ran, not time it waited for a
// core (a machine shared with other work).
inline double thread_cpu_micros() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e6 * static_cast<double>(t.tv_sec) + 1e-3 * static_cast<double>(t.tv_nsec);
}

}  // namespace medspheres::bench
