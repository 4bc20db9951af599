#include "asynevo/core/error.hpp"

#include <fmt/format.h>

namespace asynevo {

namespace {

std::string describe(const std::string& file, InputError::LocationKind kind, uint64_t location,
                     const std::string& message) {
  switch (kind) {
    case InputError::LocationKind::kLine:
      return fmt::format("{}:{}: {}", file, location, message);
    case InputError::LocationKind::kRecord:
      return fmt::format("{}: record {}: {}", file, location, message);
    case InputError::LocationKind::kByte:
      return fmt::format("{}: byte {}: {}", file, location, message);
    case InputError::LocationKind::kNone:
      break;
  }
  return fmt::format("{}: {}", file, message);
}

}  // namespace

InputError::InputError(std::string file, std::string message)
    : InputError(std::move(file), LocationKind::kNone, 0, std::move(message)) {}

InputError::InputError(std::string file, LocationKind kind, uint64_t location, std::string message)
    : Error(describe(file, kind, location, message)),
      file_(std::move(file)),
      kind_(kind),
      location_(location),
      message_(std::move(message)) {}

}  // namespace asynevo
