#include "asynevo/backend/init_attempt.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "asynevo/core/time.hpp"

namespace asynevo::backend {

std::string initAttemptsFileText(const std::vector<InitAttempt>& attempts, uint64_t not_logged) {
  std::string text =
      "# failed initialization attempts (docs/method/initialization.md): relaxations = how many times the\n"
      "# start's counts were relaxed, tracks = feature trajectories buffered, rejection = the furthest "
      "check\n"
      "# t_s relaxations tracks rejection failure\n";
  for (const InitAttempt& a : attempts) {
    std::string failure = a.failure;  // one line per attempt
    std::replace(failure.begin(), failure.end(), '\n', ' ');
    text += fmt::format("{:.9f} {} {} {} {}\n", nsToSeconds(a.t_ns), a.relaxations, a.tracks,
                        rejectionName(a.rejection), failure);
  }
  if (not_logged > 0)
    text += fmt::format("# {} later failed attempts not listed (the log keeps the first {})\n", not_logged,
                        kMaxInitAttemptsLogged);
  return text;
}

}  // namespace asynevo::backend
