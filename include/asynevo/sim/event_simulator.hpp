#pragma once
// The event camera model (ESIM-style: Rebecq, Gehrig & Scaramuzza, "ESIM: an Open Event Camera
// Simulator", CoRL 2018; sensor model after Lichtsteiner, Posch & Delbruck, JSSC 2008):
//
//   * log intensity L = log(I + ε) per pixel, rendered at adaptive times so that no scene point moves
//     more than `max_pixel_motion` pixels between two renders;
//   * each pixel keeps a reference level L_ref (its level at its last event); every crossing of
//     L_ref ± C± between two renders is an event, timestamped by linear interpolation of L in time;
//   * per-pixel thresholds C± ~ N(C, σ_C) (fixed per pixel, like transistor mismatch);
//   * refractory period: an event closer than `refractory_ns` to the pixel's previous one is dropped
//     (the reference still moves, as in ESIM);
//   * optional noise of real sensors (docs/simulator_noise.md): background activity (Poisson, uniform
//     over pixels, a chosen share of ON events), hot pixels, a slow common-mode drift of all thresholds
//     and Gaussian timestamp jitter.
// Deterministic for a seed; the result does not depend on the number of threads.

#include <cstdint>
#include <functional>
#include <vector>

#include "asynevo/core/camera/camera_model.hpp"
#include "asynevo/core/event.hpp"
#include "asynevo/sim/motion.hpp"
#include "asynevo/sim/renderer.hpp"
#include "asynevo/sim/scene.hpp"

namespace asynevo::sim {

struct EventSimConfig {
  double contrast = 0.2;            ///< mean contrast threshold C (log units), both polarities
  double contrast_sigma = 0.03;     ///< per-pixel standard deviation of C+ and C-
  double min_contrast = 0.01;       ///< thresholds are clamped below at this
  double log_epsilon = 0.01;        ///< ε in L = log(I + ε), I in [0, 1]
  int64_t refractory_ns = 100'000;  ///< 100 µs
  double noise_rate_hz = 0.0;       ///< background noise events per pixel per second (0 = off)
  double noise_on_fraction = 0.5;   ///< share of ON events among background and hot-pixel events
  int hot_pixels = 0;               ///< number of hot pixels (0 = none)
  double hot_pixel_rate_hz = 50.0;  ///< events per second of each hot pixel
  /// Amplitude D of a slow common-mode threshold drift: every threshold is C_pixel (1 + d(t)) with
  /// d(t) = D/3 Σ_k sin(2π f_k t + φ_k), three seeded sinusoids with periods of 5-30 s; |d| <= D < 0.5.
  double contrast_drift = 0.0;
  /// σ of the Gaussian jitter (truncated at 3σ) added to every event's timestamp (0 = none). The output
  /// stays time-ordered; jittered times are clamped to the simulated span.
  int64_t time_jitter_ns = 0;
  double max_pixel_motion = 0.3;    ///< max image motion between renders (pixels)
  int64_t max_step_ns = 5'000'000;  ///< longest render step (5 ms)
  int64_t min_step_ns = 1'000;      ///< shortest render step (1 µs)
  int threads = 1;  ///< worker threads for rendering and event generation (≥ 1); 2 helps only on idle cores
};

struct EventSimStats {
  uint64_t events = 0;
  uint64_t on_events = 0;
  uint64_t off_events = 0;
  uint64_t noise_events = 0;      ///< background noise and hot-pixel events (included in events)
  uint64_t background_events = 0;  ///< background noise events (part of noise_events)
  uint64_t hot_pixel_events = 0;   ///< hot-pixel events (part of noise_events)
  int hot_pixels = 0;              ///< number of hot pixels simulated
  uint64_t refractory_drops = 0;  ///< crossings dropped by the refractory period
  uint64_t render_steps = 0;
  int64_t min_step_ns = 0;
  int64_t max_step_ns = 0;
  double max_step_motion_px = 0;  ///< largest measured image motion of a step (≤ max_pixel_motion)
  double wall_seconds = 0;
};

class EventSimulator {
 public:
  /// Called once per render step with that step's events, sorted by (t, y, x, polarity).
  using EventSink = std::function<void(const std::vector<Event>&)>;
  /// Called with the linear intensity image (W*H) at each frame time.
  using FrameSink = std::function<void(int64_t t_ns, const std::vector<float>& intensity)>;

  EventSimulator(const CameraModel& camera, const Scene& scene, const EventSimConfig& config, uint64_t seed);

  /// Simulates the motion over [begin_ns, end_ns]. When `frame_period_ns` > 0, frames are delivered at
  /// begin + k * period.
  EventSimStats run(const Motion& motion, int64_t begin_ns, int64_t end_ns, const EventSink& sink,
                    int64_t frame_period_ns = 0, const FrameSink& frames = nullptr);

  /// Per-pixel thresholds (for tests): C+ and C- of pixel (x, y), without the drift.
  double contrastOn(int x, int y) const { return c_on_[index(x, y)]; }
  double contrastOff(int x, int y) const { return c_off_[index(x, y)]; }
  /// The common-mode threshold factor 1 + d(t) at `t_s` seconds after the start (exactly 1 without drift).
  double contrastScale(double t_s) const;

 private:
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(camera_.width()) +
           static_cast<std::size_t>(x);
  }
  /// Renders rows [r0, r1) at the new pose and emits the events of the step (t_a, t_b] into `out`.
  void processRows(const Renderer::Frame& frame, int64_t t_a, int64_t t_b, float contrast_scale, int r0,
                   int r1, std::vector<Event>& out, uint64_t& drops);

  const CameraModel& camera_;
  Renderer renderer_;
  EventSimConfig config_;
  uint64_t seed_;
  std::vector<float> c_on_, c_off_;
  double drift_hz_[3] = {0, 0, 0};  // the drift's sinusoids: frequencies and phases
  double drift_phase_[3] = {0, 0, 0};
  std::vector<float> intensity_;  // scratch: linear intensity at t_b
  std::vector<float> log_prev_;   // L at the previous render
  std::vector<float> log_ref_;    // L at each pixel's last event (reference)
  std::vector<int64_t> last_event_ns_;
};

}  // namespace asynevo::sim
