#pragma once
// Runs the asynevo binary as a user would and captures what it prints and its exit code.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <string>

namespace asynevo::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr, interleaved
};

/// A real sample recording of ../shared/data/formats (RELATIVE: e.g. "evt3/evt3_sample.raw"); several are
/// GPL-licensed, so they are read from there and not copied into the repository (../shared/data/SOURCES.md).
#ifdef ASYNEVO_SHARED_DATA_DIR  // defined for test_cli (tests/cli/CMakeLists.txt)
inline std::string sharedFormatSample(const std::string& relative) {
  return std::string(ASYNEVO_SHARED_DATA_DIR) + "/formats/" + relative;
}
#endif

/// Runs `asynevo <arguments>`, in `working_dir` when given (else the test's working directory).
inline CommandResult runAsynevo(const std::string& arguments, const std::string& working_dir = "") {
  const std::string cd = working_dir.empty() ? "" : "cd '" + working_dir + "' && ";
  const std::string command = cd + std::string(ASYNEVO_BINARY_DIR) + "/bin/asynevo " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Writes `content` to `path`, runs `asynevo info` on it and expects exit code 1 and the message
/// "asynevo: error: <path>: <message>".
inline void expectInfoFails(const std::string& path, const std::string& content, const std::string& message) {
  std::ofstream(path, std::ios::binary) << content;
  const CommandResult result = runAsynevo("info --dataset " + path);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("asynevo: error: " + path + ": " + message), std::string::npos)
      << "expected '" << message << "' in:\n"
      << result.output;
}

}  // namespace asynevo::testing
