#include "asynevo/eval/plot.hpp"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "asynevo/core/error.hpp"

extern char** environ;

namespace asynevo::eval {

namespace {

namespace fs = std::filesystem;

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

fs::path executableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

}  // namespace

std::string findPlotScript() {
  if (const char* dir = std::getenv("ASYNEVO_TOOLS_DIR"); dir && *dir) {
    const fs::path p = fs::path(dir) / "plot_run.py";
    if (isFile(p)) return p.string();
  }
#ifdef ASYNEVO_TOOLS_DIR
  if (const fs::path p = fs::path(ASYNEVO_TOOLS_DIR) / "plot_run.py"; isFile(p)) return p.string();
#endif
  if (const fs::path exe_dir = executableDir(); !exe_dir.empty()) {
    for (const fs::path& p : {exe_dir / ".." / "share" / "asynevo" / "tools" / "plot_run.py",
                              exe_dir / ".." / ".." / "tools" / "plot_run.py"}) {
      if (isFile(p)) return fs::weakly_canonical(p).string();
    }
  }
  return "";
}

std::string pythonInterpreter() {
  if (const char* python = std::getenv("ASYNEVO_PYTHON"); python && *python) return python;
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

int runPlotScript(const std::string& run_dir, const std::vector<std::string>& extra_args) {
  const std::string script = findPlotScript();
  if (script.empty()) {
    throw Error("cannot find tools/plot_run.py (set ASYNEVO_TOOLS_DIR to the folder that holds it)");
  }
  const std::string python = pythonInterpreter();
  std::vector<std::string> args = {python, script, "--run", run_dir};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);  // keep our output before the script's
  std::fflush(stderr);
  pid_t pid = 0;
  const int rc = python.find('/') == std::string::npos
                     ? posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ)
                     : posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (rc != 0) throw Error(fmt::format("cannot start {}: {}", python, std::strerror(rc)));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error(fmt::format("waiting for {} failed: {}", python, std::strerror(errno)));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace asynevo::eval
