#pragma once
// An owning std::FILE* that closes itself.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace asynevo {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FileHandle = std::unique_ptr<std::FILE, FileCloser>;

inline FileHandle openFile(const std::string& path, const char* mode) {
  return FileHandle(std::fopen(path.c_str(), mode));
}

/// The size of a read buffer for `path`: `largest`, or less for a smaller regular file (its size plus
/// one byte, at least `smallest`), so that a short file does not cost a large allocation per open.
inline std::size_t readBufferBytes(const std::string& path, std::size_t largest, std::size_t smallest = 4096) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) return largest;
  return std::clamp<std::size_t>(static_cast<std::size_t>(size) + 1, std::min(smallest, largest), largest);
}

}  // namespace asynevo
