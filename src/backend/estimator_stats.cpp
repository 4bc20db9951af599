// Text of the estimator statistics shared by the CLI summary and the bench tools.
#include <fmt/format.h>

#include "asynevo/backend/estimator.hpp"

namespace asynevo::backend {

std::string describeInitViews(const EstimatorStats::InitViews& views) {
  return fmt::format("{}, {:.0f} ms: {} features, {} inliers, parallax {:.1f} px, {} landmarks",
                     views.method, views.span_ms, views.features, views.inliers, views.parallax_px, views.landmarks);
}

}  // namespace asynevo::backend
