#pragma once
// The speed profile of the 'speed-ramp' motion preset (the repeated-texture experiment,
// docs/results/repeated_texture.md): walking speed, a smooth acceleration, then a constant high speed,
// all along the camera's x axis. Pure functions of time, so the preset, its tests and the experiment's
// phase table share one definition.
//
//   v(t) = v_slow                                         t < t_ramp
//        = v_slow + (v_fast − v_slow) s(x), x = (t − t_ramp)/T_ramp, 0 ≤ x < 1
//        = v_fast                                         t ≥ t_ramp + T_ramp
// with the quintic smootherstep s(x) = 6x⁵ − 15x⁴ + 10x³ (velocity and acceleration continuous), whose
// integral is x⁶ − 3x⁵ + 2.5x⁴ (1/2 at x = 1).

namespace asynevo::sim {

struct SpeedRamp {
  double slow_mps = 1.4;      ///< walking speed
  double fast_mps = 9.0;      ///< the paper's top speed
  double ramp_start_s = 2.0;  ///< end of the walking phase
  double ramp_s = 1.5;        ///< duration of the acceleration

  double rampEndS() const { return ramp_start_s + ramp_s; }
  /// Speed at t (m/s).
  double speed(double t_s) const;
  /// Distance travelled from 0 to t (m).
  double distance(double t_s) const;
};

}  // namespace asynevo::sim
