#include "isolated_call.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstring>
#include <fstream>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "medspheres/error.h"

namespace medspheres::detail {

namespace {

std::string errno_text(const char* what) {
  const int error = errno;
  return std::string(what) + ": " + std::strerror(error);
}

// Bytes of address space the process has mapped now (VmSize), 0 if unknown.
std::uint64_t mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t pages = 0;
  if (!(statm >> pages)) return 0;
  const long page = ::sysconf(_SC_PAGESIZE);
  return pages * static_cast<std::uint64_t>(page > 0 ? page : 4096);
}

// Closes every descriptor from lo to hi inclusive.
void close_fds(unsigned lo, unsigned hi) {
  if (lo > hi) return;
#ifdef SYS_close_range
  if (::syscall(SYS_close_range, lo, hi, 0u) == 0) return;
#endif
  const long max = ::sysconf(_SC_OPEN_MAX);
  const unsigned top = std::min<unsigned>(hi, max > 0 ? static_cast<unsigned>(max) - 1 : 65535u);
  for (unsigned fd = lo; fd <= top; ++fd) ::close(static_cast<int>(fd));
}

bool write_all(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// The child's side: never returns.
[[noreturn]] void run_child(int fd, pid_t parent, std::uint64_t as_limit,
                            const std::function<std::string()>& work) {
  // Die with the caller: an orphaned import would otherwise run on unwatched.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(kIsolatedWriteFailed);
  // A crash must end the child, not run the caller's crash handlers.
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE, SIGTERM})
    std::signal(sig, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);

  rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  if (as_limit > 0) {
    rlimit as{};
    if (::getrlimit(RLIMIT_AS, &as) == 0) {
      const rlim_t want = static_cast<rlim_t>(as_limit);
      if (as.rlim_cur == RLIM_INFINITY || want < as.rlim_cur) as.rlim_cur = want;
      ::setrlimit(RLIMIT_AS, &as);
    }
  }

  // Keep only stdin, stdout, stderr and the pipe.
  if (fd < 3) {
    const int moved = ::fcntl(fd, F_DUPFD, 3);
    if (moved < 0) ::_exit(kIsolatedWriteFailed);
    fd = moved;
  }
  close_fds(3, static_cast<unsigned>(fd) - 1);
  close_fds(static_cast<unsigned>(fd) + 1, UINT_MAX);

  std::string result;
  try {
    result = work();
  } catch (...) {
    ::_exit(kIsolatedWorkThrew);
  }
  if (!write_all(fd, result)) ::_exit(kIsolatedWriteFailed);
  ::_exit(0);
}

// Waits for pid, retrying on EINTR. Returns false when the child cannot be waited for
// (ECHILD: the caller ignores SIGCHLD, and the kernel reaped it).
bool reap(pid_t pid, int* status) {
  for (;;) {
    if (::waitpid(pid, status, 0) == pid) return true;
    if (errno != EINTR) return false;
  }
}

// A pidfd for pid (Linux 5.3), or -1 where the kernel or the C library has none.
int open_pidfd(pid_t pid) {
#if defined(SYS_pidfd_open) && defined(SYS_pidfd_send_signal)
  const long fd = ::syscall(SYS_pidfd_open, pid, 0u);  // close-on-exec by default
  if (fd >= 0) return static_cast<int>(fd);
#endif
  return -1;
}

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() { reset(); }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

// Kills and reaps the child unless it was reaped already: no zombie and no runaway
// import survives an exception in the parent.
//
// A signal never reaches another process that reuses the child's pid. If the caller
// ignores SIGCHLD, the kernel reaps the child the moment it exits and its pid is free
// for reuse, so kill(pid) could hit a stranger. With a pidfd (opened while the child
// provably lives, see run_isolated), the signal goes to the child or, if it is gone, to
// nobody. Without one (kernels before 5.3), the child is signalled only while waitid
// sees it still running as this process's child; the pid cannot be reused between that
// test and kill() unless the child exits and is reaped in that instant.
class Reaper {
 public:
  Reaper(pid_t pid, int pidfd) : pid_(pid), pidfd_(pidfd) {}
  ~Reaper() {
    if (pid_ > 0) kill_and_wait();
    close_pidfd();
  }
  Reaper(const Reaper&) = delete;
  Reaper& operator=(const Reaper&) = delete;
  // Waits for the child; false when its status is lost (see reap).
  bool wait(int* status) {
    const bool ok = reap(pid_, status);
    pid_ = 0;
    close_pidfd();
    return ok;
  }
  void kill_and_wait() {
    kill();
    int status = 0;
    reap(pid_, &status);
    pid_ = 0;
    close_pidfd();
  }

 private:
  void kill() {
#if defined(SYS_pidfd_open) && defined(SYS_pidfd_send_signal)
    if (pidfd_ >= 0) {
      ::syscall(SYS_pidfd_send_signal, pidfd_, SIGKILL, nullptr, 0u);
      return;
    }
#endif
    siginfo_t info{};
    if (::waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
        info.si_pid == 0)
      ::kill(pid_, SIGKILL);  // running, and still this process's child
  }
  void close_pidfd() {
    if (pidfd_ >= 0) ::close(pidfd_);
    pidfd_ = -1;
  }
  pid_t pid_;
  int pidfd_;
};

}  // namespace

std::string signal_name(int sig) {
  switch (sig) {
    case SIGSEGV:
      return "SIGSEGV";
    case SIGBUS:
      return "SIGBUS";
    case SIGABRT:
      return "SIGABRT";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGKILL:
      return "SIGKILL";
    case SIGTERM:
      return "SIGTERM";
    case SIGPIPE:
      return "SIGPIPE";
    case SIGXCPU:
      return "SIGXCPU";
    case SIGSYS:
      return "SIGSYS";
    case SIGTRAP:
      return "SIGTRAP";
    default:
      return "signal " + std::to_string(sig);
  }
}

IsolatedOutcome run_isolated(const std::function<std::string()>& work,
                             const IsolationLimits& limits, const std::string& subject) {
  using Clock = std::chrono::steady_clock;
  const std::uint64_t as_limit =
      limits.address_space_bytes > 0 ? mapped_bytes() + limits.address_space_bytes : 0;
  const std::string prefix = subject + ": ";

  // fds carries the result to the parent; go carries the parent's go-ahead to the child.
  int fds[2], go[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Error(prefix + errno_text("cannot create a pipe for the import process"));
  Fd read_end(fds[0]), write_end(fds[1]);
  if (::pipe2(go, O_CLOEXEC) != 0)
    throw Error(prefix + errno_text("cannot create a pipe for the import process"));
  Fd go_read(go[0]), go_write(go[1]);

  const pid_t parent = ::getpid();
  const Clock::time_point start = Clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw Error(prefix + errno_text("cannot start the import process (fork)"));
  if (pid == 0) {
    // Wait for the go-ahead: until the parent holds a pidfd for this process, it must
    // not exit (see Reaper). EOF instead of the byte: the parent gave up.
    ::close(fds[0]);
    ::close(go[1]);
    char byte = 0;
    ssize_t n = 0;
    while ((n = ::read(go[0], &byte, 1)) < 0 && errno == EINTR) {
    }
    if (n != 1) ::_exit(kIsolatedWriteFailed);
    ::close(go[0]);
    run_child(fds[1], parent, as_limit, work);
  }
  Reaper child(pid, open_pidfd(pid));
  go_read.reset();
  write_end.reset();
  const char byte = 1;
  while (::write(go_write.get(), &byte, 1) < 0 && errno == EINTR) {
  }
  go_write.reset();

  const bool limited = limits.timeout_seconds > 0.0;
  const auto budget = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(std::min(limits.timeout_seconds, 1e8)));
  const Clock::time_point deadline = limited ? start + budget : Clock::time_point::max();

  IsolatedOutcome out;
  char buf[1 << 16];
  for (;;) {
    int wait_ms = -1;
    if (limited) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        child.kill_and_wait();
        out.end = IsolatedOutcome::End::kTimedOut;
        return out;
      }
      wait_ms = static_cast<int>(std::min<long long>(left + 1, INT_MAX));
    }
    pollfd p{read_end.get(), POLLIN, 0};
    const int ready = ::poll(&p, 1, wait_ms);
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw Error(prefix + errno_text("poll on the import pipe failed"));
    }
    if (ready == 0) continue;  // the deadline is checked above
    const ssize_t n = ::read(read_end.get(), buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      throw Error(prefix + errno_text("reading the import pipe failed"));
    }
    if (n == 0) break;  // the child closed its end: it is exiting
    out.output.append(buf, static_cast<std::size_t>(n));
  }

  int status = 0;
  if (!child.wait(&status)) {
    out.end = IsolatedOutcome::End::kExited;
    out.code = -1;  // status lost: the caller ignores SIGCHLD
  } else if (WIFSIGNALED(status)) {
    out.end = IsolatedOutcome::End::kSignaled;
    out.code = WTERMSIG(status);
  } else {
    out.end = IsolatedOutcome::End::kExited;
    out.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return out;
}

}  // namespace medspheres::detail
