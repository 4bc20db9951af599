// Per-event cost of each frontend stage and of the whole frontend, on the bundled ECD slices, on a
// long synthetic stream (synthetic_stream.hpp) and on simulated sequences (sim_sequence.hpp; one at
// 640x480 with 120 features). Figures are printed, never asserted.
//   bench_frontend [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/core/config/frontend_config.hpp"
#include "asynevo/frontend/corner_detector.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/frontend/haste_tracker.hpp"
#include "asynevo/frontend/sae.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/event_reader.hpp"
#include "sim_sequence.hpp"
#include "synthetic_stream.hpp"

using namespace asynevo;
using namespace asynevo::frontend;

namespace {

const std::vector<Event>& slice(const std::string& name) {
  static std::map<std::string, std::vector<Event>> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache
             .emplace(name, readAllEvents(std::string(ASYNEVO_SOURCE_DIR) + "/tests/data/ecd/" + name +
                                          "/events.txt"))
             .first;
  return it->second;
}

const std::vector<Event>& synthetic() {
  // 1.5 s, ~2-3 M events/s of event time.
  static const std::vector<Event> events = bench::syntheticStream(240, 180, 1.5, 500.0);
  return events;
}

// Simulated sequences (project simulator, DAVIS240C with the ECD distortion): 2 s of the 6dof preset.
const std::vector<Event>& simulated(const std::string& scene) {
  static std::map<std::string, std::vector<Event>> cache;
  auto it = cache.find(scene);
  if (it == cache.end()) it = cache.emplace(scene, bench::simulateSequence(scene, "6dof", 2.0).events).first;
  return it->second;
}

// 0.5 s of boxes/6dof at a DVXplorer-like 640x480 sensor (~7.6 M events/s of event time), with its camera.
const bench::SimSequence& simulatedDvxplorer() {
  static const bench::SimSequence s = bench::simulateSequence("boxes", "6dof", 0.5, 1, "dvxplorer");
  return s;
}

const std::vector<Event>& stream(int index) {
  static const char* names[] = {"shapes_rotation", "poster_rotation", "boxes_rotation", "dynamic_rotation"};
  if (index == 5) return simulated("shapes");
  if (index == 6) return simulated("boxes");
  if (index == 7) return simulatedDvxplorer().events;
  return index < 4 ? slice(names[index]) : synthetic();
}
const char* streamName(int index) {
  static const char* names[] = {"shapes_rotation", "poster_rotation", "boxes_rotation", "dynamic_rotation",
                                "synthetic",       "sim shapes/6dof", "sim boxes/6dof", "sim boxes/6dof 640x480"};
  return names[index];
}

void setCounters(benchmark::State& state, std::size_t events_per_iteration) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * events_per_iteration));
  state.counters["ns/event"] =
      benchmark::Counter(static_cast<double>(state.iterations() * events_per_iteration),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_SaeUpdate(benchmark::State& state) {
  const auto& events = stream(static_cast<int>(state.range(0)));
  SurfaceOfActiveEvents sae(240, 180, 50'000'000);
  int accepted = 0;
  for (auto _ : state) {
    for (const Event& e : events) accepted += sae.update(e);
    benchmark::DoNotOptimize(accepted);
  }
  state.SetLabel(streamName(static_cast<int>(state.range(0))));
  setCounters(state, events.size());
}

void detectorBench(benchmark::State& state, DetectorKind kind) {
  const auto& events = stream(static_cast<int>(state.range(0)));
  DetectorParams params;
  params.kind = kind;
  uint64_t corners = 0;
  for (auto _ : state) {
    state.PauseTiming();
    SurfaceOfActiveEvents sae(240, 180, 50'000'000);
    CornerDetector det(sae, params);
    state.ResumeTiming();
    for (const Event& e : events) corners += det.detect(e, sae.update(e)).corner;
  }
  state.SetLabel(streamName(static_cast<int>(state.range(0))));
  state.counters["corner %"] =
      100.0 * static_cast<double>(corners) / static_cast<double>(state.iterations() * events.size());
  setCounters(state, events.size());
}
void BM_SaeAndFaHarris(benchmark::State& state) { detectorBench(state, DetectorKind::kFaHarris); }
void BM_SaeAndArcStar(benchmark::State& state) { detectorBench(state, DetectorKind::kArcStar); }

// One tracker fed only in-range events (an L corner moving slowly): cost per in-range event.
void hasteBench(benchmark::State& state, HasteVariant variant) {
  std::vector<Event> events;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> along(0.f, 14.f);
  for (int i = 0; i < 200000; ++i) {
    const double t = i * 5e-6;
    const float cx = 100.f + 3.f * std::sin(float(t) * 6.f), cy = 90.f + 3.f * std::cos(float(t) * 5.f);
    const float a = along(rng);
    const bool h = rng() & 1u;
    events.push_back(Event{int64_t(t * 1e9), uint16_t(std::lround(cx + (h ? a : 0.f))),
                           uint16_t(std::lround(cy + (h ? 0.f : a))), 1});
  }
  HasteParams params;
  params.variant = variant;
  auto tracker = makeHasteTracker(params);
  uint64_t changes = 0, used = 0;
  for (auto _ : state) {
    tracker->reset(0, 103.f, 93.f);
    for (const Event& e : events) {
      const TrackerResult r = tracker->push(e.t_ns, e.x, e.y);
      changes += r == TrackerResult::kStateChanged;
      used += r != TrackerResult::kOutOfRange;
    }
  }
  state.counters["in-range %"] =
      100.0 * static_cast<double>(used) / static_cast<double>(state.iterations() * events.size());
  state.counters["switch %"] =
      100.0 * static_cast<double>(changes) / static_cast<double>(std::max<uint64_t>(1, used));
  setCounters(state, events.size());
}
void BM_HasteDifferenceStar(benchmark::State& state) { hasteBench(state, HasteVariant::kDifferenceStar); }
void BM_HasteCorrelationStar(benchmark::State& state) { hasteBench(state, HasteVariant::kCorrelationStar); }

class NullSink final : public MeasurementSink {
 public:
  void onMeasurement(const TrackMeasurement& m) override { sum += m.x; }
  double sum = 0;
};

void frontendBench(benchmark::State& state, const std::string& tracker) {
  const int index = static_cast<int>(state.range(0));
  const auto& events = stream(index);
  FrontendConfig config;
  config.tracker = tracker;
  if (state.range(1) > 0) config.max_features = static_cast<int>(state.range(1));
  if (state.range(2) == 0) {  // without the drift, rotation and neighbour-motion tests (for their cost)
    config.max_drift_px = 0;
    config.max_rotation_deg = 0;
    config.max_neighbour_disagreement_px = 0;
  }
  if (state.range(2) == 2) {  // the defaults without the neighbour-motion test (for its cost)
    config.max_neighbour_disagreement_px = 0;
  }
  if (state.range(2) == 3) config.subpixel_method = "template_fit";  // the continuous sub-pixel fit
  if (state.range(2) == 4) config.neighbour_motion_model = "either";  // the neighbour test with two references
  // Stream 7 is 640x480 with its own camera; the others are 240x180 (ECD calibration).
  const CameraModel camera =
      index == 7 ? simulatedDvxplorer().camera
                 : readEcdCalibration(std::string(ASYNEVO_SOURCE_DIR) + "/tests/data/ecd/shapes_rotation/calib.txt");
  EventPacket packet;  // the stream as one packet, as the CLI feeds a reader's packets
  packet.events = events;
  FrontendStats stats;
  for (auto _ : state) {
    state.PauseTiming();
    auto fe = std::make_unique<Frontend>(config, camera);
    NullSink sink;
    state.ResumeTiming();
    fe->process(packet, sink);
    state.PauseTiming();
    stats = fe->stats();
    fe.reset();
    state.ResumeTiming();
  }
  state.SetLabel(streamName(index));
  state.counters["Mev/s stream"] = stats.perSecond(stats.events) * 1e-6;
  state.counters["features"] = stats.meanActiveFeatures();
  state.counters["updates/ev"] =
      static_cast<double>(stats.tracker_updates) / static_cast<double>(stats.events);
  state.counters["detect/ev"] = static_cast<double>(stats.detector_runs) / static_cast<double>(stats.events);
  state.counters["meas/s"] = stats.perSecond(stats.measurements);
  state.counters["created"] = static_cast<double>(stats.features_created);
  for (DropReason reason :
       {DropReason::kQuality, DropReason::kDrift, DropReason::kRotation, DropReason::kNeighbour,
        DropReason::kBorder, DropReason::kIdle, DropReason::kCollision})
    state.counters[std::string("drop ") + dropReasonName(reason)] =
        static_cast<double>(stats.features_dropped[static_cast<int>(reason)]);
  state.counters["switch %"] =
      100.0 * static_cast<double>(stats.state_changes) / static_cast<double>(stats.tracker_updates);
  setCounters(state, events.size());
}
void BM_FrontendDifferenceStar(benchmark::State& state) { frontendBench(state, "haste_difference_star"); }
void BM_FrontendCorrelationStar(benchmark::State& state) { frontendBench(state, "haste_correlation_star"); }

}  // namespace

BENCHMARK(BM_SaeUpdate)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SaeAndArcStar)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SaeAndFaHarris)->DenseRange(0, 4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HasteDifferenceStar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HasteCorrelationStar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrontendDifferenceStar)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5, 6}, {0}, {1}})
    ->Args({4, 100, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrontendCorrelationStar)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5, 6}, {0}, {1}})
    ->Args({4, 100, 1})
    ->Args({7, 120, 1})
    ->Args({4, 100, 3})
    ->Args({7, 120, 3})
    ->Args({7, 120, 4})
    ->Args({5, 0, 4})
    ->Args({5, 0, 0})
    ->Args({6, 0, 0})
    ->Args({5, 0, 2})
    ->Args({6, 0, 2})
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
