#include "asynevo/io/skip_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"

namespace asynevo {

namespace {

class SkippingReader : public EventReader {
 public:
  SkippingReader(std::unique_ptr<EventReader> inner, int64_t skip_ns) : inner_(std::move(inner)), skip_ns_(skip_ns) {}

  bool read(EventPacket& packet) override {
    while (inner_->read(packet)) {
      if (past_cut_) return true;
      if (!started_) {
        started_ = true;
        first_ns_ = packet.frontTime();
      }
      last_ns_ = packet.backTime();
      const auto cut = std::find_if(packet.events.begin(), packet.events.end(),
                                    [&](const Event& e) { return e.t_ns - first_ns_ >= skip_ns_; });
      const auto dropped = static_cast<uint64_t>(cut - packet.events.begin());
      skipped_ += dropped;
      if (cut == packet.events.end()) continue;
      packet.events.erase(packet.events.begin(), cut);
      packet.first_index += dropped;
      past_cut_ = true;
      return true;
    }
    if (started_ && !past_cut_)
      throw InputError(info().path, fmt::format("no event is left after skipping the first {:.3f} s: the stream "
                                                "spans {:.3f} s ({} events)",
                                                nsToSeconds(skip_ns_), durationSeconds(first_ns_, last_ns_), skipped_));
    return false;
  }
  const StreamInfo& info() const override { return inner_->info(); }
  const ReaderStats& stats() const override {
    stats_ = inner_->stats();
    stats_.events -= std::min(stats_.events, skipped_);
    stats_.skipped_at_start = skipped_;
    return stats_;
  }

 private:
  std::unique_ptr<EventReader> inner_;
  int64_t skip_ns_;
  bool started_ = false, past_cut_ = false;
  int64_t first_ns_ = 0, last_ns_ = 0;
  uint64_t skipped_ = 0;
  mutable ReaderStats stats_;
};

}  // namespace

std::unique_ptr<EventReader> skipStartOfStream(std::unique_ptr<EventReader> reader, int64_t skip_ns) {
  if (skip_ns < 0) throw std::invalid_argument(fmt::format("skipStartOfStream: skip_ns must be >= 0, not {}", skip_ns));
  if (skip_ns == 0) return reader;
  return std::make_unique<SkippingReader>(std::move(reader), skip_ns);
}

}  // namespace asynevo
