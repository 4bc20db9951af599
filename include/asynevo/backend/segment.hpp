#pragma once
// Segments of the estimate (docs/method/tracking_loss.md): a segment starts at an initialization and
// ends when tracking is lost or the stream ends. Each has its own map, scale and gauge; the trajectory
// files hold the knots of all segments, and segments.txt says where each starts and ends and why.

#include <cstdint>
#include <string>
#include <vector>

namespace asynevo::backend {

/// Why a segment ended.
enum class SegmentEnd {
  kEventGap,     ///< no event for longer than loss_max_event_gap_ms
  kUnsupported,  ///< fewer than loss_min_landmarks landmarks for longer than loss_unsupported_ms
  kResidual,     ///< median reprojection error of the window above loss_max_median_px after a solve
  kDepth,        ///< median landmark depth changed by more than loss_depth_ratio since the start (scale collapse)
  kNonFinite,    ///< a state of the window became NaN or infinite
  kReversal,     ///< the direction audit found the depth-reversed motion fits better (direction_audit: restart)
  kEndOfStream,  ///< the stream ended while tracking
};
constexpr int kSegmentEndCount = 7;

/// "event_gap", "unsupported", "residual", "depth", "non_finite", "reversal", "end_of_stream".
const char* segmentEndName(SegmentEnd end);

struct Segment {
  int64_t t0_ns = 0;  ///< first knot written
  int64_t t1_ns = 0;  ///< last knot written
  uint64_t knots = 0;  ///< knots written (0: the segment ended before any knot became final)
  int64_t initialized_at_ns = 0;  ///< event time of the initialization that started it
  int64_t ended_at_ns = 0;        ///< event time at which it ended
  SegmentEnd end = SegmentEnd::kEndOfStream;
};

/// segments.txt: a comment header, then `index start_s end_s knots ended_by` per segment with knots
/// (segments that wrote no knot are left out: they have no poses to evaluate).
std::string segmentsFileText(const std::vector<Segment>& segments);

}  // namespace asynevo::backend
