#pragma once
/// \file
/// The thread count every `threads` option of medspheres takes (BakeOptions,
/// DilateOptions, FitOptions, the CLI's --threads): 0 for all cores (OpenMP's default
/// team size), or an explicit count from 1 to kMaxThreads. The cap keeps a typo such as
/// 100000 from asking the OpenMP runtime for more threads than the system can create
/// (which crashes it); 1024 is far above the cores of any machine this runs on, and
/// results are bit-identical for every count anyway.

#include <stdexcept>
#include <string>

namespace medspheres {

/// The largest explicit thread count accepted.
inline constexpr int kMaxThreads = 1024;

/// \throws std::invalid_argument "threads must be in [0, 1024] (0: all cores), got N"
///   unless 0 <= threads <= kMaxThreads.
inline void check_threads(int threads) {
  if (threads < 0 || threads > kMaxThreads)
    throw std::invalid_argument("threads must be in [0, " + std::to_string(kMaxThreads) +
                                "] (0: all cores), got " + std::to_string(threads));
}

}  // namespace medspheres
