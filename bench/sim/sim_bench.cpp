// Simulator speed: one rendered frame per scene, and simulated seconds of the 6dof preset.
#include <benchmark/benchmark.h>

#include "asynevo/sim/event_simulator.hpp"
#include "asynevo/sim/renderer.hpp"
#include "asynevo/sim/scene.hpp"

namespace asynevo::sim {
namespace {

const char* kScenes[] = {"shapes", "checkerboard", "stripes", "blobs", "poster", "boxes", "room"};

void BM_RenderFrame(benchmark::State& state) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const auto motion = makePresetMotion("6dof", 2.0);
  const Scene scene = makeBuiltinScene(kScenes[state.range(0)], *motion, camera, 1);
  const Renderer renderer(camera, scene);
  std::vector<float> image(static_cast<std::size_t>(camera.width() * camera.height()));
  int64_t t = 0;
  for (auto _ : state) {
    const Renderer::Frame frame = renderer.prepare(motion->pose(t));
    renderer.render(frame, image.data(), 0, camera.height());
    benchmark::DoNotOptimize(image.data());
    t = (t + 1'000'000) % 2'000'000'000;
  }
  state.SetLabel(kScenes[state.range(0)]);
  state.counters["pixels/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * camera.width() * camera.height(),
                         benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrame)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);

// One simulated second of 6dof motion in front of the shapes plane (threads = argument).
void BM_SimulateSecond(benchmark::State& state) {
  const CameraModel camera = CameraModel::davis240cEcd();
  const auto motion = makePresetMotion("6dof", 1.0);
  const Scene scene = makeBuiltinScene("shapes", *motion, camera, 1);
  EventSimConfig config;
  config.threads = static_cast<int>(state.range(0));
  uint64_t events = 0, steps = 0;
  for (auto _ : state) {
    EventSimulator simulator(camera, scene, config, 1);
    const EventSimStats stats =
        simulator.run(*motion, motion->beginNs(), motion->endNs(),
                      [](const std::vector<Event>& e) { benchmark::DoNotOptimize(e.data()); });
    events += stats.events;
    steps += stats.render_steps;
  }
  state.counters["events/s"] = benchmark::Counter(static_cast<double>(events), benchmark::Counter::kIsRate);
  state.counters["steps"] = static_cast<double>(steps) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_SimulateSecond)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

}  // namespace
}  // namespace asynevo::sim

BENCHMARK_MAIN();
