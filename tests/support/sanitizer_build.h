#pragma once
// Whether this test program is built with AddressSanitizer or ThreadSanitizer (CI's
// sanitizer stages, .ci/run and .ci/tsan), whose instrumentation runs the code several times
// slower. A test whose input size sets only how long it runs, not which code it reaches,
// takes a smaller input there; its checks stay the same. A test that repeats, on a larger
// input, what another test already runs under the sanitizers is left out of those builds
// (docs/reliability.md lists them). Header-only.

// The same as a macro, for a test case that is left out of those builds altogether.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)  // GCC
#define MEDSPHERES_TEST_SANITIZER_BUILD 1
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define MEDSPHERES_TEST_SANITIZER_BUILD 1
#endif
#endif
#ifndef MEDSPHERES_TEST_SANITIZER_BUILD
#define MEDSPHERES_TEST_SANITIZER_BUILD 0
#endif

#include <cstddef>
#include <vector>

namespace medspheres::test {

inline constexpr bool kSanitizerBuild = MEDSPHERES_TEST_SANITIZER_BUILD != 0;

/// The budgets (sphere counts) a test runs: \p full, or in the sanitizer builds \p sanitized,
/// a few of full's chosen so that the test still reaches the same branches.
inline std::vector<std::size_t> budgets(std::vector<std::size_t> full,
                                        std::vector<std::size_t> sanitized) {
  return kSanitizerBuild ? sanitized : full;
}

}  // namespace medspheres::test
