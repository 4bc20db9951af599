#pragma once
// Errors with context. Every problem with user input names where it was found: the file and the
// line (text formats), the record (binary formats of fixed-size records) or the byte offset (binary
// streams of variable-length words, e.g. Prophesee RAW), so the user can open the file and look.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace asynevo {

/// Base class of all AsynEVO errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad or unreadable input: a file that is missing, truncated, malformed or inconsistent.
/// what() reads "<file>:<line>: <message>", "<file>: record <n>: <message>" or "<file>: byte <n>: <message>".
class InputError : public Error {
 public:
  enum class LocationKind { kNone, kLine, kRecord, kByte };

  InputError(std::string file, std::string message);
  InputError(std::string file, LocationKind kind, uint64_t location, std::string message);

  static InputError atLine(std::string file, uint64_t line, std::string message) {
    return InputError(std::move(file), LocationKind::kLine, line, std::move(message));
  }
  static InputError atRecord(std::string file, uint64_t record, std::string message) {
    return InputError(std::move(file), LocationKind::kRecord, record, std::move(message));
  }
  static InputError atByte(std::string file, uint64_t offset, std::string message) {
    return InputError(std::move(file), LocationKind::kByte, offset, std::move(message));
  }

  const std::string& file() const { return file_; }
  LocationKind locationKind() const { return kind_; }
  /// Line number (1-based), record index (0-based) or byte offset from the file's start (0-based),
  /// depending on locationKind().
  uint64_t location() const { return location_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  LocationKind kind_ = LocationKind::kNone;
  uint64_t location_ = 0;
  std::string message_;
};

/// A configuration value that is missing, of the wrong type or out of range.
class ConfigError : public Error {
 public:
  using Error::Error;
};

}  // namespace asynevo
