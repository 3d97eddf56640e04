#pragma once
// Private: runs a helper program in a child process under resource limits and returns the
// bytes it produced, so that a crash, an endless loop or a runaway allocation in
// third-party code (assimp) cannot take the calling process down. POSIX and Linux only.
//
// The caller starts the helper with posix_spawn (no fork of the caller's threads and
// locks: the helper is a fresh program); the helper's main hands its work to
// serve_isolated, which speaks the other side of the protocol below.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace medspheres::detail {

struct IsolationLimits {
  double timeout_seconds = 0.0;  ///< wall clock, from the start of the child to its exit; 0: none
  /// Address space the child may map beyond what it has mapped when it starts serving
  /// (RLIMIT_AS); 0: none.
  std::uint64_t address_space_bytes = 0;
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

/// Starts \p program (posix_spawn, with every signal at its default and none blocked) as
/// `program --isolated <caller pid> <address_space_bytes> args...`, its descriptor 3 the
/// write end of the result pipe and 4 the read end of a go-ahead pipe; 0, 1 and 2 are
/// the caller's. The go-ahead is sent once the caller holds a pidfd for the child (so
/// that no signal meant for it can reach a process that reuses its pid). The caller reads
/// the result pipe as the child writes it (poll() with the deadline, so that a large result
/// cannot fill the pipe and stall both), kills the child at the deadline, and always reaps
/// it, also when it throws itself.
/// \throws medspheres::Error starting with "<subject>: " when the pipe or the process
///   cannot be created, or the pipe cannot be read.
IsolatedOutcome run_isolated(const std::string& program, const std::vector<std::string>& args,
                             const IsolationLimits& limits, const std::string& subject);

/// The child's side, for the helper's main(): checks the arguments run_isolated passes
/// (false, and nothing done, when they are not those: the program was run by hand), asks
/// to be killed if the caller dies, waits for the go-ahead, sets its limits (RLIMIT_AS, no
/// core file), closes every descriptor but 0 to 3, runs \p work on the remaining
/// arguments, writes its result to descriptor 3 and leaves with _exit (status 0, or
/// kIsolatedWorkThrew / kIsolatedWriteFailed). Returns only when it returns false.
bool serve_isolated(int argc, char** argv,
                    const std::function<std::string(const std::vector<std::string>&)>& work);

/// "SIGSEGV" for 11, and so on; "signal N" for a number without a name.
std::string signal_name(int sig);

}  // namespace medspheres::detail
