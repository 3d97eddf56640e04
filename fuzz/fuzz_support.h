#pragma once
// What every fuzz target shares: the bytes as text, the one failure a reader may report
// for bad input (InputError), and a check that stays on in every build type.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "medspheres/error.h"

namespace medspheres::fuzz {

inline std::string text_of(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs \p f and says whether it accepted its input. An InputError is a reader's answer to
/// bad input; any other exception escapes to libFuzzer, which reports it as a crash.
template <class F>
bool accepts(F&& f) {
  try {
    f();
    return true;
  } catch (const InputError&) {
    return false;
  }
}

[[noreturn]] inline void check_failed(const char* what, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: fuzz check failed: %s\n", file, line, what);
  std::abort();
}

}  // namespace medspheres::fuzz

#define MEDSPHERES_FUZZ_CHECK(cond) \
  ((cond) ? (void)0 : ::medspheres::fuzz::check_failed(#cond, __FILE__, __LINE__))
