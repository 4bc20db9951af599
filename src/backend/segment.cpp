#include "asynevo/backend/segment.hpp"

#include <fmt/format.h>

#include "asynevo/core/time.hpp"

namespace asynevo::backend {

const char* segmentEndName(SegmentEnd end) {
  switch (end) {
    case SegmentEnd::kEventGap: return "event_gap";
    case SegmentEnd::kUnsupported: return "unsupported";
    case SegmentEnd::kResidual: return "residual";
    case SegmentEnd::kDepth: return "depth";
    case SegmentEnd::kNonFinite: return "non_finite";
    case SegmentEnd::kReversal: return "reversal";
    case SegmentEnd::kEndOfStream: return "end_of_stream";
  }
  return "unknown";
}

std::string segmentsFileText(const std::vector<Segment>& segments) {
  std::string text =
      "# segments of the estimate (docs/method/tracking_loss.md): each has its own map and scale\n"
      "# index start_s end_s knots ended_by\n";
  int index = 0;
  for (const Segment& s : segments) {
    if (s.knots == 0) continue;
    text += fmt::format("{} {:.9f} {:.9f} {} {}\n", index++, nsToSeconds(s.t0_ns), nsToSeconds(s.t1_ns), s.knots,
                        segmentEndName(s.end));
  }
  return text;
}

}  // namespace asynevo::backend
