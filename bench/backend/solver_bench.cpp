// One Levenberg–Marquardt iteration of a GP bundle-adjustment window (issue 5; reference figure on
// this machine class: ~11 ms per iteration for 20 knots / 300 landmarks / 3000 measurements, DENSE_SCHUR,
// 2 threads). Each benchmark iteration rebuilds the problem from the same perturbed start (not timed)
// and runs 10 LM iterations (timed). Counters per LM iteration: wall_ms (whole Solve ÷ iterations,
// including Ceres' preprocessing), eval_ms (residual + Jacobian evaluation) and linear_ms (linear solve).
//
// Args: knots, landmarks, measurements per landmark, linear solver (0 DENSE_SCHUR, 1 SPARSE_SCHUR),
// threads.

#include <benchmark/benchmark.h>
#include <ceres/ceres.h>

#include <chrono>

#include "testing/gp_ba_sim.hpp"

namespace asynevo {
namespace {

constexpr int kLmIterations = 10;

void BM_LmIteration(benchmark::State& st) {
  testing::GpBaConfig config;
  config.knots = static_cast<int>(st.range(0));
  config.landmarks = static_cast<int>(st.range(1));
  config.measurements_per_landmark = static_cast<int>(st.range(2));
  const ceres::LinearSolverType solver = st.range(3) == 0 ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  const testing::GpBaScenario s = testing::makeGpBaScenario(config);

  double wall_s = 0.0;
  double eval_s = 0.0;
  double linear_s = 0.0;
  int64_t lm_iterations = 0;
  for (auto _ : st) {
    st.PauseTiming();
    testing::GpBaState x = testing::perturbedState(s, 5);
    ceres::Problem problem;
    testing::buildGpBaProblem(s, x, problem, /*huber=*/1.5);
    problem.SetParameterBlockConstant(x.poses.front().data());
    problem.SetParameterBlockConstant(x.poses.back().data());
    ceres::Solver::Options options;
    options.linear_solver_type = solver;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.max_num_iterations = kLmIterations;
    options.function_tolerance = 0.0;
    options.gradient_tolerance = 0.0;
    options.parameter_tolerance = 0.0;
    options.num_threads = static_cast<int>(st.range(4));
    ceres::Solver::Summary summary;
    st.ResumeTiming();
    const auto start = std::chrono::steady_clock::now();
    ceres::Solve(options, &problem, &summary);
    const auto stop = std::chrono::steady_clock::now();
    st.PauseTiming();
    wall_s += std::chrono::duration<double>(stop - start).count();
    lm_iterations += static_cast<int64_t>(summary.iterations.size()) - 1;  // iteration 0 is the start
    eval_s += summary.residual_evaluation_time_in_seconds + summary.jacobian_evaluation_time_in_seconds;
    linear_s += summary.linear_solver_time_in_seconds;
    st.ResumeTiming();
  }
  st.counters["measurements"] = static_cast<double>(s.measurements.size());
  st.counters["lm_iterations"] =
      benchmark::Counter(static_cast<double>(lm_iterations), benchmark::Counter::kAvgIterations);
  st.counters["wall_ms_per_lm_it"] = 1e3 * wall_s / static_cast<double>(lm_iterations);
  st.counters["eval_ms_per_lm_it"] = 1e3 * eval_s / static_cast<double>(lm_iterations);
  st.counters["linear_ms_per_lm_it"] = 1e3 * linear_s / static_cast<double>(lm_iterations);
}

void lmArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"knots", "landmarks", "meas_per_lm", "sparse", "threads"});
  for (int sparse : {0, 1}) {
    b->Args({10, 100, 10, sparse, 2});
    b->Args({20, 300, 10, sparse, 2});
    b->Args({40, 300, 10, sparse, 2});
    b->Args({40, 500, 12, sparse, 2});
    b->Args({20, 300, 10, sparse, 1});
  }
  b->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_LmIteration)->Apply(lmArgs);

}  // namespace
}  // namespace asynevo
