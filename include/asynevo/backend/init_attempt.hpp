#pragma once
// The log of failed initialization attempts (docs/method/initialization.md, "Why a start waits"): when,
// at which relaxation of the counts, with how many feature trajectories, and why each attempt did not
// start. A run writes it as init_attempts.txt; stats.json keeps only the counts by reason.

#include <cstdint>
#include <string>
#include <vector>

#include "asynevo/backend/init_result.hpp"

namespace asynevo::backend {

struct InitAttempt {
  int64_t t_ns = 0;     ///< event time of the attempt
  int relaxations = 0;  ///< 0, 1 or 2: how many times the counts were relaxed for it
  int tracks = 0;       ///< feature trajectories buffered for the start
  InitRejection rejection = InitRejection::None;  ///< the furthest check it reached
  std::string failure;                            ///< which check failed, with the counts
};

/// Failed attempts kept in memory: a stream that never starts tries 20 times a second, and the log of a
/// long one is cut here (the number left out is counted and written).
inline constexpr std::size_t kMaxInitAttemptsLogged = 20000;

/// init_attempts.txt: a comment header, then `t_s relaxations tracks rejection failure` per attempt, and
/// a last comment line with the number of attempts not listed, when there are any.
std::string initAttemptsFileText(const std::vector<InitAttempt>& attempts, uint64_t not_logged);

/// init_reversals.txt: a comment header, then per comparison with a depth-reversed alternative
/// `t_a_s t_b_s method features cost reversed_cost tx ty tz rx ry rz decision` (the translation
/// directions x_b = R x_a + t of the motion and of its alternative; the alternative's cost and direction
/// are 0 when none was found).
std::string initReversalsFileText(const std::vector<ReversalCheck>& checks);

}  // namespace asynevo::backend
