#include "asynevo/frontend/event_rate_budget.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace asynevo::frontend {

EventRateBudget::EventRateBudget(double max_rate_ev_s, int64_t window_ns) : window_ns_(window_ns) {
  if (!(max_rate_ev_s > 0) || window_ns <= 0) throw std::invalid_argument("EventRateBudget: rate and window must be positive");
  budget_ = std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(max_rate_ev_s * static_cast<double>(window_ns) * 1e-9)));
}

void EventRateBudget::openWindow(int64_t t_ns) {
  // The previous window's count decides this one's stride, unless the stream was silent in between.
  const bool adjacent = window_end_ns_ != INT64_MIN && t_ns < window_end_ns_ + window_ns_;
  const uint64_t previous = adjacent ? count_ : 0;
  stride_ = previous > 2 * budget_ ? (previous + 2 * budget_ - 1) / (2 * budget_) : 1;
  window_end_ns_ = t_ns + window_ns_;
  count_ = 0;
}

}  // namespace asynevo::frontend
