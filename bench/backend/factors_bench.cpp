// Factor evaluation cost (issue 5 target: ≤ 2 µs per projection residual with Jacobians).
// One benchmark iteration = one CostFunction::Evaluate on the next factor of a simulated window.

#include <benchmark/benchmark.h>

#include <array>
#include <memory>
#include <vector>

#include "testing/gp_ba_sim.hpp"

namespace asynevo {
namespace {

struct ProjectionFixture {
  testing::GpBaScenario scenario = testing::makeGpBaScenario(testing::GpBaConfig{});
  testing::GpBaState state = testing::perturbedState(scenario, 3);
  std::vector<std::unique_ptr<backend::GpProjectionFactor>> factors;
  std::vector<std::array<const double*, 5>> params;

  ProjectionFixture() {
    for (const testing::GpBaMeasurement& m : scenario.measurements) {
      const int k = m.knot;
      factors.push_back(std::make_unique<backend::GpProjectionFactor>(
          m.z, m.t_ns, scenario.knot_times_ns[k], scenario.knot_times_ns[k + 1], scenario.config.sigma));
      params.push_back({state.poses[k].data(), state.velocities[k].data(), state.poses[k + 1].data(),
                        state.velocities[k + 1].data(), state.landmarks[m.landmark].data()});
    }
  }
};

void BM_GpProjectionFactor(benchmark::State& st) {
  const bool with_jacobians = st.range(0) != 0;
  const ProjectionFixture f;
  double residuals[2];
  std::array<double, 2 * 7> j0{}, j2{};
  std::array<double, 2 * 6> j1{}, j3{};
  std::array<double, 2 * 3> j4{};
  double* jacobians[] = {j0.data(), j1.data(), j2.data(), j3.data(), j4.data()};
  size_t i = 0;
  for (auto _ : st) {
    const bool ok =
        f.factors[i]->Evaluate(f.params[i].data(), residuals, with_jacobians ? jacobians : nullptr);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(residuals);
    benchmark::DoNotOptimize(j4);
    if (++i == f.factors.size()) i = 0;
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_GpProjectionFactor)->Arg(0)->Arg(1)->ArgName("jacobians");

void BM_WnoaPriorFactor(benchmark::State& st) {
  const bool with_jacobians = st.range(0) != 0;
  const testing::GpBaScenario s = testing::makeGpBaScenario(testing::GpBaConfig{});
  testing::GpBaState x = testing::perturbedState(s, 3);
  const backend::WnoaPriorFactor factor(s.knot_times_ns[0], s.knot_times_ns[1], lie::Mat6::Identity());
  double residuals[12];
  std::array<double, 12 * 7> j0{}, j2{};
  std::array<double, 12 * 6> j1{}, j3{};
  double* jacobians[] = {j0.data(), j1.data(), j2.data(), j3.data()};
  size_t k = 0;
  for (auto _ : st) {
    const double* params[] = {x.poses[k].data(), x.velocities[k].data(), x.poses[k + 1].data(),
                              x.velocities[k + 1].data()};
    const bool ok = factor.Evaluate(params, residuals, with_jacobians ? jacobians : nullptr);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(residuals);
    benchmark::DoNotOptimize(j3);
    if (++k + 1 == x.poses.size()) k = 0;
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_WnoaPriorFactor)->Arg(0)->Arg(1)->ArgName("jacobians");

}  // namespace
}  // namespace asynevo
