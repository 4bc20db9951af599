#pragma once
// Helpers for I/O tests: a private temporary folder per test and small file writers.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "asynevo/core/error.hpp"
#include "asynevo/io/event_reader.hpp"

namespace asynevo::testing {

/// A fresh folder under the system temp dir, removed when the test ends.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    // The process id keeps copies of the same test (other build folders, ctest -j) apart.
    path_ = std::filesystem::temp_directory_path() / (std::string("asynevo_") + info->test_suite_name() + "_" +
                                                      info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& content) const {
    std::ofstream(file(name), std::ios::binary) << content;
    return file(name);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string dataPath(const std::string& relative) {
  return std::string(ASYNEVO_SOURCE_DIR) + "/tests/data/" + relative;
}

/// An event at `t_us` microseconds; polarity +1 or -1.
inline Event ev(int64_t t_us, int x, int y, int polarity) {
  Event e;
  e.t_ns = t_us * 1000;
  e.x = static_cast<uint16_t>(x);
  e.y = static_cast<uint16_t>(y);
  e.polarity = static_cast<int8_t>(polarity);
  return e;
}

/// The message of the InputError that reading all of `path` throws, or "" when there is none.
inline std::string errorOf(const std::string& path, const ReaderOptions& options = {}) {
  try {
    readAllEvents(path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// Expects reading `path` to fail with "<path>: byte <offset>: <text>..." (the message may continue).
inline void expectErrorAt(const std::string& path, uint64_t offset, const std::string& text,
                          const ReaderOptions& options = {}) {
  const std::string message = errorOf(path, options);
  const std::string expected = path + ": byte " + std::to_string(offset) + ": " + text;
  EXPECT_EQ(message.substr(0, expected.size()), expected) << "full message: " << message;
}

}  // namespace asynevo::testing
