#pragma once
// Private: runs a function in a forked child process under resource limits and returns
// the bytes it produced, so that a crash, an endless loop or a runaway allocation in
// third-party code (assimp) cannot take the calling process down. POSIX and Linux only.

#include <cstdint>
#include <functional>
#include <string>

namespace medspheres::detail {

struct IsolationLimits {
  double timeout_seconds = 0.0;           ///< wall clock, from fork to exit; 0: none
  std::uint64_t address_space_bytes = 0;  ///< RLIMIT_AS of the child; 0: none
};

struct IsolatedOutcome {
  enum class End {
    kExited,    ///< the child exited; code is its exit status
    kSignaled,  ///< the child was killed by signal code (not by us)
    kTimedOut,  ///< the child ran past the timeout and was killed
  };
  End end = End::kExited;
  int code = 0;
  std::string output;  ///< what work() returned, or a prefix of it if the child died
};

/// Exit status of a child whose work() threw, and of one that could not send its result.
constexpr int kIsolatedWorkThrew = 121;
constexpr int kIsolatedWriteFailed = 122;

/// Forks; the child waits until the parent holds a pidfd for it (so that no signal
/// meant for it can reach a process that reuses its pid), sets its limits (RLIMIT_AS, no
/// core file), closes every descriptor but 0, 1, 2 and its end of the pipe, asks to be
/// killed if the caller dies, runs \p work, writes its result to the pipe and leaves
/// with _exit (no atexit handlers, no stdio flush). The parent reads the pipe as the
/// child writes it (poll() with the deadline, so a large result cannot fill the pipe and
/// stall both), kills the child at the deadline, and always reaps it, also when it
/// throws itself.
///
/// The child of a multi-threaded caller holds only the forking thread; work() must not
/// depend on locks other threads may hold (glibc's malloc and stdio are safe after
/// fork; C++ streams and locales are not guaranteed to be). Do whatever can be done
/// before the call in the caller, and keep work() to the third-party code it isolates.
/// \throws medspheres::Error starting with "<subject>: " when the pipe or the process
///   cannot be created, or the pipe cannot be read.
IsolatedOutcome run_isolated(const std::function<std::string()>& work,
                             const IsolationLimits& limits, const std::string& subject);

/// "SIGSEGV" for 11, and so on; "signal N" for a number without a name.
std::string signal_name(int sig);

}  // namespace medspheres::detail
