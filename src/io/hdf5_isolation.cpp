#include "hdf5_isolation.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>

#include "asynevo/core/error.hpp"
#include "asynevo/io/file_handle.hpp"

// Set by the sanitizer runtimes when a build uses them (weak: null otherwise). libFuzzer registers its
// crash reporter through it; the child clears it, so a crash there is the child's only.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace asynevo::io_detail {

namespace {

bool inside_child = false;

/// Resident bytes of a process (/proc/PID/statm), 0 when unknown.
uint64_t residentBytes(pid_t pid) {
  std::ifstream statm(fmt::format("/proc/{}/statm", pid));
  uint64_t size_pages = 0, resident_pages = 0;
  if (!(statm >> size_pages >> resident_pages)) return 0;
  return resident_pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

[[noreturn]] void runChild(const std::function<void()>& parse) {
  inside_child = true;
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  // The default action for the crash signals: the parent reads the signal from the exit status (a
  // fuzzer's or a sanitizer's handler would report the crash as the parent's).
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(sig, &action, nullptr);
  int code = 0;
  try {
    parse();
  } catch (...) {
    code = 2;  // an error libhdf5 or the reader reported: the caller's own parse reports it
  }
  _exit(code);  // no atexit handlers, no stdio flush: the parent owns those
}

}  // namespace

bool hasHdf5Signature(const std::string& path) {
  FileHandle file = openFile(path, "rb");
  unsigned char head[sizeof kHdf5Signature] = {};
  return file && std::fread(head, 1, sizeof head, file.get()) == sizeof head &&
         std::memcmp(head, kHdf5Signature, sizeof head) == 0;
}

bool insideHdf5Child() { return inside_child; }

Hdf5ChildLimits& defaultHdf5ChildLimits() {
  static Hdf5ChildLimits limits;
  return limits;
}

void parseHdf5InChild(const std::string& path, const std::function<void()>& parse,
                      const Hdf5ChildLimits& limits) {
  if (inside_child) {
    parse();
    return;
  }
  if (!limits.fork) return;  // unguarded: the caller's own parse is the file's only one
  const uint64_t resident_at_fork = residentBytes(getpid());
  // The child holds the write end of a pipe it never writes: its end closes the pipe and wakes the
  // parent at once, which otherwise looks at the child's memory and time every few milliseconds.
  int wake[2] = {-1, -1};
  if (pipe2(wake, O_CLOEXEC) != 0) return;  // no pipe (descriptor limit): the caller parses unguarded
  const pid_t pid = fork();
  if (pid < 0) {  // no child possible (process limit): the caller parses unguarded, as without this check
    close(wake[0]);
    close(wake[1]);
    return;
  }
  if (pid == 0) {
    close(wake[0]);
    runChild(parse);
  }
  close(wake[1]);

  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  std::string stopped;
  while (true) {
    pollfd fd{wake[0], POLLIN, 0};
    const int ready = poll(&fd, 1, 5);  // ms
    const pid_t done = waitpid(pid, &status, ready > 0 ? 0 : WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      close(wake[0]);
      throw InputError(path, fmt::format("waiting for the HDF5 check failed: {}", std::strerror(errno)));
    }
    const uint64_t resident = residentBytes(pid);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (resident > resident_at_fork && resident - resident_at_fork > limits.max_resident_bytes) {
      stopped =
          fmt::format("libhdf5 took more than {} MiB of memory reading the file's structure and was stopped",
                      limits.max_resident_bytes >> 20);
    } else if (seconds > limits.max_seconds) {
      stopped = fmt::format("libhdf5 took more than {:g} s reading the file's structure and was stopped",
                            limits.max_seconds);
    }
    if (!stopped.empty()) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      close(wake[0]);
      throw InputError(path, stopped + ": a corrupt HDF5 file (a valid one needs far less)");
    }
  }
  close(wake[0]);
  if (WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 2)) return;
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    throw InputError(path,
                     fmt::format("libhdf5 crashed (signal {}, {}) reading the file's structure: a corrupt "
                                 "HDF5 file",
                                 sig, strsignal(sig)));
  }
  throw InputError(path,
                   fmt::format("libhdf5 failed (exit code {}) reading the file's structure: a corrupt HDF5 "
                               "file",
                               WIFEXITED(status) ? WEXITSTATUS(status) : -1));
}

}  // namespace asynevo::io_detail
