#include "asynevo/io/repeat_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "asynevo/core/error.hpp"

namespace asynevo {

namespace {

class RepeatingReader : public EventReader {
 public:
  RepeatingReader(std::function<std::unique_ptr<EventReader>()> open, int passes)
      : open_(std::move(open)), passes_(passes), current_(open_()), info_(current_->info()) {}

  bool read(EventPacket& packet) override {
    while (true) {
      if (current_->read(packet)) {
        if (pass_events_ == 0) pass_first_ns_ = packet.frontTime();
        pass_last_ns_ = packet.backTime();
        pass_events_ += packet.size();
        packet.first_index += stats_.events - (pass_events_ - packet.size());
        for (Event& e : packet.events) e.t_ns += offset_ns_;
        stats_.events += packet.size();
        return true;
      }
      accumulate(current_->stats());
      if (pass_events_ == 0)
        throw InputError(info_.path, fmt::format("pass {} of the repeated stream has no events", pass_ + 1));
      if (++pass_ >= passes_) return false;
      // The next pass starts one mean event interval after this one's last event.
      const int64_t span = pass_last_ns_ - pass_first_ns_;
      const int64_t gap = std::max<int64_t>(1, span / static_cast<int64_t>(std::max<uint64_t>(1, pass_events_)));
      offset_ns_ += span + gap;
      pass_events_ = 0;
      current_ = open_();
    }
  }
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  void accumulate(const ReaderStats& s) {
    stats_.clamped_times += s.clamped_times;
    stats_.skipped_lines += s.skipped_lines;
    stats_.rectified_outside += s.rectified_outside;
  }

  std::function<std::unique_ptr<EventReader>()> open_;
  int passes_;
  int pass_ = 0;
  std::unique_ptr<EventReader> current_;
  StreamInfo info_;
  ReaderStats stats_;
  uint64_t pass_events_ = 0;
  int64_t pass_first_ns_ = 0, pass_last_ns_ = 0;
  int64_t offset_ns_ = 0;
};

}  // namespace

std::unique_ptr<EventReader> repeatEvents(std::function<std::unique_ptr<EventReader>()> open, int passes) {
  if (passes < 1) throw std::invalid_argument(fmt::format("repeatEvents: passes must be >= 1, not {}", passes));
  return std::make_unique<RepeatingReader>(std::move(open), passes);
}

}  // namespace asynevo
