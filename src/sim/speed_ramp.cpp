#include "asynevo/sim/speed_ramp.hpp"

#include <algorithm>

namespace asynevo::sim {

namespace {
double smootherstep(double x) { return x * x * x * (x * (6 * x - 15) + 10); }
double smootherstepIntegral(double x) { return x * x * x * x * (x * (x - 3) + 2.5); }
}  // namespace

double SpeedRamp::speed(double t_s) const {
  const double x = std::clamp((t_s - ramp_start_s) / ramp_s, 0.0, 1.0);
  return slow_mps + (fast_mps - slow_mps) * smootherstep(x);
}

double SpeedRamp::distance(double t_s) const {
  const double t = std::max(t_s, 0.0);
  const double x = std::clamp((t - ramp_start_s) / ramp_s, 0.0, 1.0);
  const double after = std::max(0.0, t - rampEndS());
  return slow_mps * t + (fast_mps - slow_mps) * (ramp_s * smootherstepIntegral(x) + after);
}

}  // namespace asynevo::sim
