#pragma once
// A peak-rate budget for the frontend (docs/method/frontend.md, "Peak event rates"): when a burst brings
// more events than the frontend can process, it sheds work by a rule of event time and event counts
// only, so an offline run and a real-time run of the same stream shed the same events.
//
// Event time is cut into windows of `window_ns`, each opened by the first event after the previous one
// closed. With B = the budget's events per window:
//  * the first B events of a window are processed in full;
//  * later events of the window still update the SAE and the trackers, but do not run the corner
//    detector (no new features from a burst: `detections skipped`);
//  * when the previous window held n > 2B events, this window keeps one event in every ⌈n / 2B⌉ and
//    sheds the rest before the SAE and the trackers (`events shed`), so the trackers see about 2B
//    events per window however dense the burst. A window that follows a gap starts with no shedding.
// Nothing is shed uncounted.

#include <cstdint>

namespace asynevo::frontend {

class EventRateBudget {
 public:
  enum class Decision { kFull, kTrackOnly, kShed };

  /// max_rate_ev_s > 0: events per second of event time processed in full.
  EventRateBudget(double max_rate_ev_s, int64_t window_ns);

  /// What to do with the next event, at t_ns (non-decreasing).
  Decision admit(int64_t t_ns) {
    if (t_ns >= window_end_ns_) openWindow(t_ns);
    ++count_;
    if (stride_ > 1 && count_ % stride_ != 0) return Decision::kShed;
    return count_ > budget_ ? Decision::kTrackOnly : Decision::kFull;
  }

  uint64_t budget() const { return budget_; }
  uint64_t stride() const { return stride_; }

 private:
  void openWindow(int64_t t_ns);

  int64_t window_ns_;
  uint64_t budget_;
  int64_t window_end_ns_ = INT64_MIN;
  uint64_t count_ = 0;
  uint64_t stride_ = 1;
};

}  // namespace asynevo::frontend
