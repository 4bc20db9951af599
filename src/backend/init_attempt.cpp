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

std::string initReversalsFileText(const std::vector<ReversalCheck>& checks) {
  std::string text =
      "# comparisons of a start's motion with its depth-reversed alternative (docs/method/depth_reversal.md):\n"
      "# cost = chirality cost; t = translation direction from the first view to the second, x_b = R x_a + t;\n"
      "# reversed_* = the alternative's (0 when none was found); parallax_px = an audit's median parallax with\n"
      "# the rotation removed (0 for a start); decision = kept, reversed or tie (a start), kept, against or\n"
      "# restart (an audit of a young segment, method audit)\n"
      "# t_a_s t_b_s method features parallax_px cost reversed_cost tx ty tz rx ry rz decision\n";
  for (const ReversalCheck& c : checks) {
    text += fmt::format("{:.9f} {:.9f} {} {} {:.2f} {:.4f} {:.4f} {:.5f} {:.5f} {:.5f} {:.5f} {:.5f} {:.5f} {}\n",
                        nsToSeconds(c.t_a_ns), nsToSeconds(c.t_b_ns), c.method, c.features, c.parallax_px, c.cost,
                        c.found ? c.reversed_cost : 0.0, c.t_b_a.x(), c.t_b_a.y(), c.t_b_a.z(), c.reversed_t_b_a.x(),
                        c.reversed_t_b_a.y(), c.reversed_t_b_a.z(), c.decision);
  }
  return text;
}

}  // namespace asynevo::backend
