#pragma once
// An owning std::FILE* that closes itself.

#include <cstdio>
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

}  // namespace asynevo
