#pragma once
// Whether this test program is built with AddressSanitizer or ThreadSanitizer (CI's
// sanitizer stages, .ci/run and .ci/tsan), whose instrumentation runs the code several times
// slower. A test whose input size sets only how long it runs, not which code it reaches,
// takes a smaller input there; its checks stay the same. Header-only.

namespace medspheres::test {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)  // GCC
inline constexpr bool kSanitizerBuild = true;
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif
#else
inline constexpr bool kSanitizerBuild = false;
#endif

}  // namespace medspheres::test
