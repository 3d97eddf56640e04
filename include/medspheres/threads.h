#pragma once
/// \file
/// The thread count every `threads` option of medspheres takes (BakeOptions,
/// DilateOptions, FitOptions, the CLI's --threads): 0 for all cores (OpenMP's default
/// team size), or an explicit count from 1 to kMaxThreads. Results are bit-identical for
/// every count.

#include <stdexcept>
#include <string>

namespace medspheres {

/// The largest explicit thread count accepted (why 1024: threads.cpp).
inline constexpr int kMaxThreads = 1024;

/// What is wrong with \p threads as a thread count, "must be in [0, 1024] (0: all cores),
/// got N", or an empty string when 0 <= threads <= kMaxThreads.
inline std::string threads_problem(int threads) {
  if (threads >= 0 && threads <= kMaxThreads) return {};
  return "must be in [0, " + std::to_string(kMaxThreads) + "] (0: all cores), got " +
         std::to_string(threads);
}

/// \throws std::invalid_argument "threads must be in [0, 1024] (0: all cores), got N"
///   unless 0 <= threads <= kMaxThreads.
inline void check_threads(int threads) {
  const std::string problem = threads_problem(threads);
  if (!problem.empty()) throw std::invalid_argument("threads " + problem);
}

/// The size of the thread team a `threads` option asks for: \p threads itself when it is
/// 1 to kMaxThreads, and for 0 OpenMP's default team size (omp_get_max_threads(), at most
/// kMaxThreads). Every parallel loop of medspheres takes its team size from here.
/// \throws std::invalid_argument as check_threads.
int thread_count(int threads);

}  // namespace medspheres
