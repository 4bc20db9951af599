#include "asynevo/backend/incremental_estimator.hpp"

#include <cmath>
#include <iterator>

namespace asynevo::backend {

namespace {
EstimatorOptions withoutMarginalization(EstimatorOptions options, const IncrementalOptions& incremental) {
  options.marginalize = false;
  // The whole history is one banded system: a sparse factorization keeps the growth near linear
  // where the window's DENSE_SCHUR would be cubic (and would overstate the baseline's cost).
  options.sparse_linear_solver = !incremental.frozen;
  return options;
}
}  // namespace

IncrementalEstimator::IncrementalEstimator(EstimatorOptions options, const IncrementalOptions& incremental)
    : SlidingWindowEstimator(withoutMarginalization(std::move(options), incremental)),
      incremental_(incremental),
      trigger_ns_(std::llround(incremental.trigger_ms * 1e6)) {}

void IncrementalEstimator::addMeasurement(const TrackMeasurement& m) {
  SlidingWindowEstimator::addMeasurement(m);
  ++measurements_since_solve_;
}

void IncrementalEstimator::advanceTo(int64_t t_ns) {
  const uint64_t updates_before = stats().updates;
  SlidingWindowEstimator::advanceTo(t_ns);  // a new knot triggers an update as in the window estimator
  if (!tracking()) return;
  if (stats().updates != updates_before) {
    last_solve_ns_ = t_ns;
    measurements_since_solve_ = 0;
    return;
  }
  // New trajectory measurements trigger a re-optimization of the history (Liu et al.'s asynchronous
  // trigger), rate-limited in event time so the cost stays finite.
  if (measurements_since_solve_ > 0 && t_ns - last_solve_ns_ >= trigger_ns_) {
    update(t_ns);
    last_solve_ns_ = t_ns;
    measurements_since_solve_ = 0;
  }
}

bool IncrementalEstimator::isFrozen(const Knot& knot) const {
  if (!incremental_.frozen) return false;
  const auto& knots = trajectory().knots();
  if (static_cast<int>(knots.size()) <= incremental_.active_knots) return false;
  const int64_t boundary = std::prev(knots.end(), incremental_.active_knots)->first;
  return knot.t_ns < boundary;
}

}  // namespace asynevo::backend
