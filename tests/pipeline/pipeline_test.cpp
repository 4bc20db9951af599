#include "asynevo/pipeline/pipeline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "asynevo/core/error.hpp"
#include "synthetic_events.hpp"

namespace asynevo::pipeline {
namespace {

// --- MarkerClock ---

std::vector<int64_t> markersOf(const std::vector<int64_t>& times, int64_t period) {
  MarkerClock clock(period);
  std::vector<int64_t> markers;
  for (int64_t t : times) {
    int64_t m = 0;
    if (clock.next(t, m)) markers.push_back(m);
  }
  return markers;
}

TEST(MarkerClock, EmitsEachMultipleOfThePeriodOnceWhenEventTimeReachesIt) {
  EXPECT_EQ(markersOf({1'500'000, 1'900'000, 2'000'000, 2'000'001, 2'999'999, 3'100'000}, 1'000'000),
            (std::vector<int64_t>{2'000'000, 3'000'000}));
}

TEST(MarkerClock, AJumpOverSeveralMultiplesGivesTheLargestOne) {
  EXPECT_EQ(markersOf({500, 7'250'000, 7'300'000, 8'000'000}, 1'000'000),
            (std::vector<int64_t>{7'000'000, 8'000'000}));
}

TEST(MarkerClock, TheFirstEventNeverEmitsAndNegativeTimesFloorCorrectly) {
  EXPECT_EQ(markersOf({3'000'000}, 1'000'000), std::vector<int64_t>{});
  EXPECT_EQ(markersOf({-1'500'000, -1'000'000, -1}, 1'000'000), (std::vector<int64_t>{-1'000'000}));
  EXPECT_THROW(MarkerClock(0), std::invalid_argument);
}

// --- Pipeline ---

/// Serves events from memory in packets of a chosen size; can fail after a number of packets.
class VectorReader final : public EventReader {
 public:
  VectorReader(std::vector<Event> events, int packet_size, int fail_after_packets = -1)
      : events_(std::move(events)), packet_size_(packet_size), fail_after_(fail_after_packets) {
    info_.path = "memory";
    info_.format = "test";
    info_.width = 120;
    info_.height = 100;
  }
  bool read(EventPacket& packet) override {
    if (fail_after_ >= 0 && packets_ == fail_after_)
      throw InputError::atRecord("memory", next_, "bad record");
    packet.events.clear();
    packet.first_index = next_;
    while (next_ < events_.size() && packet.events.size() < static_cast<std::size_t>(packet_size_))
      packet.events.push_back(events_[next_++]);
    stats_.events = next_;
    ++packets_;
    return !packet.events.empty();
  }
  const StreamInfo& info() const override { return info_; }
  const ReaderStats& stats() const override { return stats_; }

 private:
  std::vector<Event> events_;
  int packet_size_;
  int fail_after_;
  int packets_ = 0;
  std::size_t next_ = 0;
  StreamInfo info_;
  ReaderStats stats_;
};

/// Records every call as text; hands out one fake knot per marker so the outputs path is exercised.
class RecordingEstimator final : public backend::Estimator {
 public:
  const char* name() const override { return "recording"; }
  void addMeasurement(const TrackMeasurement& m) override {
    log << "m " << m.feature_id << ' ' << m.t_ns << ' ' << m.x << ' ' << m.y << '\n';
    ++measurements;
  }
  void endFeature(int64_t id) override { log << "e " << id << '\n'; }
  void advanceTo(int64_t t_ns) override {
    log << "a " << t_ns << '\n';
    if (throw_at_marker >= 0 && ++markers > throw_at_marker) throw std::runtime_error("estimator failure");
    backend::Knot k;
    k.t_ns = t_ns;
    pending_.push_back(k);
  }
  void finish() override {
    log << "finish\n";
    finished = true;
  }
  std::vector<backend::Knot> takeFinalKnots() override { return std::exchange(pending_, {}); }
  std::vector<backend::UpdateRecord> takeUpdateRecords() override { return {}; }
  std::vector<backend::LandmarkPoint> takeFinalLandmarks() override { return {}; }
  const backend::EstimatorStats& stats() const override { return stats_; }

  std::ostringstream log;
  uint64_t measurements = 0;
  bool finished = false;
  int throw_at_marker = -1;
  int markers = 0;

 private:
  std::vector<backend::Knot> pending_;
  backend::EstimatorStats stats_;
};

class CountingOutput final : public PipelineOutput {
 public:
  void onMeasurement(const TrackMeasurement&) override { ++measurements; }
  void onFinalKnots(const std::vector<backend::Knot>& k) override {
    for (const auto& knot : k) knot_times.push_back(knot.t_ns);
  }
  uint64_t measurements = 0;
  std::vector<int64_t> knot_times;
};

std::vector<Event> squareEvents() {
  using frontend::testing::MovingSquare;
  const std::vector<MovingSquare> squares = {
      {20, 20, 18, 40, 10}, {70, 50, 14, -30, 20}, {40, 60, 12, 20, -25}};
  return frontend::testing::simulateSquares(squares, 120, 100, 0.4);
}

struct Outcome {
  std::string log;
  PipelineStats stats;
  CountingOutput output;
};

Outcome runOnce(const std::vector<Event>& events, int packet_size, std::size_t queue_capacity,
                std::size_t chunk_items) {
  VectorReader reader(events, packet_size);
  FrontendConfig config;
  frontend::Frontend fe(config, 120, 100);
  RecordingEstimator estimator;
  Outcome outcome;
  PipelineOptions options;
  options.queue_capacity = queue_capacity;
  options.max_chunk_items = chunk_items;
  Pipeline pipeline(reader, fe, estimator, outcome.output, options);
  outcome.stats = pipeline.run();
  EXPECT_TRUE(estimator.finished);
  outcome.log = estimator.log.str();
  return outcome;
}

TEST(Pipeline, TheBackendCallSequenceDoesNotDependOnPacketSizeQueueCapacityOrChunking) {
  const std::vector<Event> events = squareEvents();
  ASSERT_GT(events.size(), 5000u);
  const Outcome reference = runOnce(events, 65536, 1024, 1024);
  ASSERT_GT(reference.stats.measurements, 50u) << "the synthetic squares must produce tracks";
  ASSERT_GT(reference.stats.markers, 100u);
  for (const auto& [packet, capacity, chunk] :
       {std::tuple<int, std::size_t, std::size_t>{1, 1, 1}, {97, 2, 7}, {5000, 3, 100000}}) {
    const Outcome other = runOnce(events, packet, capacity, chunk);
    EXPECT_EQ(other.log, reference.log)
        << "packet " << packet << " capacity " << capacity << " chunk " << chunk;
  }
}

TEST(Pipeline, MarkersAreIncreasingMillisecondsAndEveryMeasurementReachesEstimatorAndOutput) {
  const std::vector<Event> events = squareEvents();
  const Outcome o = runOnce(events, 4096, 16, 64);
  std::istringstream in(o.log);
  std::string kind;
  int64_t previous_marker = 0;
  uint64_t markers = 0, measurements = 0;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    l >> kind;
    if (kind == "a") {
      int64_t t = 0;
      l >> t;
      EXPECT_EQ(t % 1'000'000, 0);
      if (markers > 0) {
        EXPECT_GT(t, previous_marker);
      }
      previous_marker = t;
      ++markers;
    } else if (kind == "m") {
      ++measurements;
    }
  }
  EXPECT_EQ(markers, o.stats.markers);
  EXPECT_EQ(measurements, o.stats.measurements);
  EXPECT_EQ(o.output.measurements, o.stats.measurements);
  EXPECT_EQ(o.output.knot_times.size(), markers);  // the fake estimator finalizes one knot per marker
  EXPECT_EQ(o.stats.events, events.size());
  EXPECT_EQ(o.stats.first_t_ns, events.front().t_ns);
  EXPECT_EQ(o.stats.last_t_ns, events.back().t_ns);
  // The last line is finish().
  EXPECT_EQ(o.log.substr(o.log.size() - 7), "finish\n");
}

TEST(Pipeline, AReaderErrorStopsBothThreadsAndIsRethrown) {
  VectorReader reader(squareEvents(), 1000, 3);
  frontend::Frontend fe(FrontendConfig{}, 120, 100);
  RecordingEstimator estimator;
  CountingOutput output;
  Pipeline pipeline(reader, fe, estimator, output, {});
  EXPECT_THROW(pipeline.run(), InputError);
  EXPECT_FALSE(estimator.finished);
}

TEST(Pipeline, AnEstimatorErrorStopsTheFrontendAndIsRethrown) {
  VectorReader reader(squareEvents(), 1000);
  frontend::Frontend fe(FrontendConfig{}, 120, 100);
  RecordingEstimator estimator;
  estimator.throw_at_marker = 20;
  CountingOutput output;
  PipelineOptions options;
  options.queue_capacity = 2;
  Pipeline pipeline(reader, fe, estimator, output, options);
  EXPECT_THROW(pipeline.run(), std::runtime_error);
  EXPECT_FALSE(estimator.finished);
}

}  // namespace
}  // namespace asynevo::pipeline
