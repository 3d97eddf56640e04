#include "isolated_call.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
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

// Descriptors of the child: the result pipe and the go-ahead pipe.
constexpr int kResultFd = 3;
constexpr int kGoFd = 4;

// Parses a decimal unsigned number that fills all of \p text.
bool parse_u64(const char* text, std::uint64_t* out) {
  if (text == nullptr || *text < '0' || *text > '9') return false;
  errno = 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (errno != 0 || *end != '\0') return false;
  *out = v;
  return true;
}

// The child's limits: no core file, and RLIMIT_AS at what it maps now plus \p extra.
void set_child_limits(std::uint64_t extra) {
  rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  if (extra == 0) return;
  rlimit as{};
  if (::getrlimit(RLIMIT_AS, &as) != 0) return;
  const rlim_t want = static_cast<rlim_t>(mapped_bytes() + extra);
  if (as.rlim_cur == RLIM_INFINITY || want < as.rlim_cur) as.rlim_cur = want;
  ::setrlimit(RLIMIT_AS, &as);
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
  void reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
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

namespace {

// A descriptor of the child, moved to kGoFd + 1 or above (close-on-exec), so that the
// spawn's dup2 onto kResultFd and kGoFd cannot overwrite one with the other.
int above_child_fds(Fd& fd, const std::string& prefix) {
  if (fd.get() > kGoFd) return fd.get();
  const int moved = ::fcntl(fd.get(), F_DUPFD_CLOEXEC, kGoFd + 1);
  if (moved < 0) throw Error(prefix + errno_text("cannot create a pipe for the import process"));
  fd.reset(moved);
  return moved;
}

// Starts program with the two pipe ends as its kResultFd and kGoFd, every signal at its
// default and none blocked. Returns the child's pid.
pid_t spawn_child(const std::string& program, const std::vector<std::string>& argv, int result_fd,
                  int go_fd, const std::string& prefix) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  if (::posix_spawn_file_actions_init(&actions) != 0 || ::posix_spawnattr_init(&attr) != 0)
    throw Error(prefix + "cannot start the import process: out of memory");
  sigset_t all, none;
  sigfillset(&all);
  sigemptyset(&none);
  ::posix_spawn_file_actions_adddup2(&actions, result_fd, kResultFd);
  ::posix_spawn_file_actions_adddup2(&actions, go_fd, kGoFd);
  ::posix_spawnattr_setsigdefault(&attr, &all);
  ::posix_spawnattr_setsigmask(&attr, &none);
  ::posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  pid_t pid = 0;
  const int error = ::posix_spawn(&pid, program.c_str(), &actions, &attr, args.data(), environ);
  ::posix_spawn_file_actions_destroy(&actions);
  ::posix_spawnattr_destroy(&attr);
  if (error != 0)
    throw Error(prefix + "cannot start the import process " + program + ": " +
                std::strerror(error));
  return pid;
}

}  // namespace

bool serve_isolated(int argc, char** argv,
                    const std::function<std::string(const std::vector<std::string>&)>& work) {
  std::uint64_t parent = 0, as_limit = 0;
  if (argc < 4 || std::strcmp(argv[1], "--isolated") != 0 || !parse_u64(argv[2], &parent) ||
      !parse_u64(argv[3], &as_limit))
    return false;
  // Die with the caller: an orphaned import would otherwise run on unwatched.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (static_cast<std::uint64_t>(::getppid()) != parent) ::_exit(kIsolatedWriteFailed);
  // Wait for the go-ahead: until the caller holds a pidfd for this process, it must not
  // exit (see Reaper). EOF instead of the byte: the caller gave up.
  char byte = 0;
  ssize_t n = 0;
  while ((n = ::read(kGoFd, &byte, 1)) < 0 && errno == EINTR) {
  }
  if (n != 1) ::_exit(kIsolatedWriteFailed);
  set_child_limits(as_limit);
  // Keep only stdin, stdout, stderr and the result pipe.
  close_fds(kGoFd, UINT_MAX);

  std::string result;
  try {
    result = work(std::vector<std::string>(argv + 4, argv + argc));
  } catch (...) {
    ::_exit(kIsolatedWorkThrew);
  }
  if (!write_all(kResultFd, result)) ::_exit(kIsolatedWriteFailed);
  ::_exit(0);
}

IsolatedOutcome run_isolated(const std::string& program, const std::vector<std::string>& args,
                             const IsolationLimits& limits, const std::string& subject) {
  using Clock = std::chrono::steady_clock;
  const std::string prefix = subject + ": ";

  // fds carries the result to the caller; go carries the caller's go-ahead to the child.
  int fds[2], go[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Error(prefix + errno_text("cannot create a pipe for the import process"));
  Fd read_end(fds[0]), write_end(fds[1]);
  if (::pipe2(go, O_CLOEXEC) != 0)
    throw Error(prefix + errno_text("cannot create a pipe for the import process"));
  Fd go_read(go[0]), go_write(go[1]);

  std::vector<std::string> argv{program, "--isolated", std::to_string(::getpid()),
                                std::to_string(limits.address_space_bytes)};
  argv.insert(argv.end(), args.begin(), args.end());
  const Clock::time_point start = Clock::now();
  const pid_t pid = spawn_child(program, argv, above_child_fds(write_end, prefix),
                                above_child_fds(go_read, prefix), prefix);
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
