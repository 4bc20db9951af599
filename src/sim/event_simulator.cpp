#include "asynevo/sim/event_simulator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "asynevo/core/time.hpp"
#include "asynevo/sim/random.hpp"

namespace asynevo::sim {

namespace {

constexpr int64_t kNever = INT64_MIN / 2;

bool eventLess(const Event& a, const Event& b) {
  if (a.t_ns != b.t_ns) return a.t_ns < b.t_ns;
  if (a.y != b.y) return a.y < b.y;
  if (a.x != b.x) return a.x < b.x;
  return a.polarity < b.polarity;
}

}  // namespace

EventSimulator::EventSimulator(const CameraModel& camera, const Scene& scene, const EventSimConfig& config,
                               uint64_t seed)
    : camera_(camera), renderer_(camera, scene), config_(config), seed_(seed) {
  if (!(config.contrast > 0) || !(config.min_contrast > 0)) {
    throw std::invalid_argument(
        fmt::format("the contrast threshold (--contrast) must be positive, got {}", config.contrast));
  }
  if (!(config.contrast_sigma >= 0)) {
    throw std::invalid_argument(fmt::format(
        "the threshold spread (--contrast-sigma) must not be negative, got {}", config.contrast_sigma));
  }
  if (!(config.log_epsilon > 0)) throw std::invalid_argument("log_epsilon must be positive");
  if (!(config.max_pixel_motion > 0)) {
    throw std::invalid_argument(fmt::format(
        "the render step's image motion (--max-step-motion) must be positive, got {}", config.max_pixel_motion));
  }
  if (config.min_step_ns <= 0 || config.max_step_ns < config.min_step_ns) {
    throw std::invalid_argument("render step bounds must satisfy 0 < min_step_ns <= max_step_ns");
  }
  if (config.refractory_ns < 0) {
    throw std::invalid_argument(fmt::format("the refractory period (--refractory-us) must not be negative, got {} us",
                                            static_cast<double>(config.refractory_ns) / 1e3));
  }
  if (!(config.noise_rate_hz >= 0) || !std::isfinite(config.noise_rate_hz)) {
    throw std::invalid_argument(
        fmt::format("the background rate (--noise-rate) must not be negative, got {}", config.noise_rate_hz));
  }
  if (config.hot_pixels < 0) {
    throw std::invalid_argument(
        fmt::format("the hot-pixel count (--hot-pixels) must not be negative, got {}", config.hot_pixels));
  }
  if (!(config.hot_pixel_rate_hz >= 0) || !std::isfinite(config.hot_pixel_rate_hz)) {
    throw std::invalid_argument(fmt::format(
        "the hot-pixel rate (--hot-pixel-rate) must not be negative, got {}", config.hot_pixel_rate_hz));
  }
  if (!(config.noise_on_fraction >= 0 && config.noise_on_fraction <= 1)) {
    throw std::invalid_argument(fmt::format(
        "the ON share of noise events (--noise-on-fraction) must be in [0, 1], got {}", config.noise_on_fraction));
  }
  if (!(config.contrast_drift >= 0 && config.contrast_drift < 0.5)) {
    throw std::invalid_argument(fmt::format(
        "the threshold drift (--contrast-drift) must be in [0, 0.5), got {}", config.contrast_drift));
  }
  if (config.time_jitter_ns < 0) {
    throw std::invalid_argument(fmt::format("the timestamp jitter (--time-jitter-us) must not be negative, got {} us",
                                            static_cast<double>(config.time_jitter_ns) / 1e3));
  }
  const std::size_t n = static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height());
  Random rng(seed ^ 0x434F4E5452415354ULL);  // "CONTRAST"
  c_on_.resize(n);
  c_off_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    c_on_[i] = static_cast<float>(
        std::max(config.min_contrast, config.contrast + config.contrast_sigma * rng.normal()));
    c_off_[i] = static_cast<float>(
        std::max(config.min_contrast, config.contrast + config.contrast_sigma * rng.normal()));
  }
  // The drift's three sinusoids: periods 5-30 s, random phases (own generator, so the drift does not
  // change any other random draw).
  Random drift_rng(seed ^ 0x4452494654000000ULL);  // "DRIFT"
  for (int k = 0; k < 3; ++k) {
    drift_hz_[k] = 1.0 / (5.0 + 25.0 * drift_rng.uniform());
    drift_phase_[k] = 6.283185307179586 * drift_rng.uniform();
  }
  intensity_.resize(n);
  log_prev_.resize(n);
  log_ref_.resize(n);
  last_event_ns_.assign(n, kNever);
}

double EventSimulator::contrastScale(double t_s) const {
  if (config_.contrast_drift == 0) return 1.0;
  double sum = 0;
  for (int k = 0; k < 3; ++k) sum += std::sin(6.283185307179586 * drift_hz_[k] * t_s + drift_phase_[k]);
  return 1.0 + config_.contrast_drift * sum / 3.0;
}

void EventSimulator::processRows(const Renderer::Frame& frame, int64_t t_a, int64_t t_b, float contrast_scale,
                                 int r0, int r1, std::vector<Event>& out, uint64_t& drops) {
  renderer_.render(frame, intensity_.data(), r0, r1);
  const int w = camera_.width();
  const auto eps = static_cast<float>(config_.log_epsilon);
  const double dt = static_cast<double>(t_b - t_a);
  for (int y = r0; y < r1; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = index(x, y);
      const float l_b = std::log(intensity_[i] + eps);
      const float l_a = log_prev_[i];
      log_prev_[i] = l_b;
      const float dl = l_b - l_a;
      if (dl == 0.0f) continue;
      float ref = log_ref_[i];
      const float c = (dl > 0 ? c_on_[i] : c_off_[i]) * contrast_scale;  // exact when the scale is 1
      const int8_t polarity = dl > 0 ? 1 : -1;
      // Every crossing of ref ± C between L(t_a) and L(t_b), in order; L is linear in t in between.
      while (polarity > 0 ? (l_b - ref >= c) : (ref - l_b >= c)) {
        ref += polarity * c;
        const double frac = std::clamp(static_cast<double>(ref - l_a) / static_cast<double>(dl), 0.0, 1.0);
        const int64_t t = t_a + std::llround(frac * dt);
        if (t - last_event_ns_[i] < config_.refractory_ns) {
          ++drops;
          continue;
        }
        last_event_ns_[i] = t;
        out.push_back(Event{t, static_cast<uint16_t>(x), static_cast<uint16_t>(y), polarity});
      }
      log_ref_[i] = ref;
    }
  }
}

EventSimStats EventSimulator::run(const Motion& motion, int64_t begin_ns, int64_t end_ns,
                                  const EventSink& sink, int64_t frame_period_ns, const FrameSink& frames) {
  const auto wall_start = std::chrono::steady_clock::now();
  EventSimStats stats;
  if (end_ns < begin_ns) throw std::invalid_argument("simulation ends before it begins");
  const int w = camera_.width(), h = camera_.height();
  const int threads = std::clamp(config_.threads, 1, 64);

  // Initial render: every pixel's reference is its level at the start (no events at t = begin).
  StampedPose pose_a = motion.pose(begin_ns);
  {
    const Renderer::Frame frame = renderer_.prepare(pose_a);
    renderer_.render(frame, intensity_.data(), 0, h);
    for (std::size_t i = 0; i < intensity_.size(); ++i) {
      log_prev_[i] = std::log(intensity_[i] + static_cast<float>(config_.log_epsilon));
      log_ref_[i] = log_prev_[i];
    }
    std::fill(last_event_ns_.begin(), last_event_ns_.end(), kNever);
  }
  int64_t next_frame_ns = begin_ns;
  const auto emitFrame = [&](int64_t t) {
    if (frame_period_ns > 0 && frames) frames(t, renderer_.render(motion.pose(t)));
  };
  if (frame_period_ns > 0) {
    emitFrame(next_frame_ns);
    next_frame_ns += frame_period_ns;
  }

  // Noise: one Poisson process over all pixels, hot pixels each with their own (deterministic for the seed).
  Random noise_rng(seed_ ^ 0x4E4F495345000000ULL);  // "NOISE"
  const double total_noise_rate = config_.noise_rate_hz * w * h;
  int64_t next_noise_ns =
      total_noise_rate > 0 ? begin_ns + secondsToNs(noise_rng.exponential(total_noise_rate)) : INT64_MAX;
  struct HotPixel {
    uint16_t x, y;
    int64_t next_ns;
  };
  std::vector<HotPixel> hot;
  for (int k = 0; k < config_.hot_pixels && config_.hot_pixel_rate_hz > 0; ++k) {
    const auto x = static_cast<uint16_t>(noise_rng.uniform() * w);
    const auto y = static_cast<uint16_t>(noise_rng.uniform() * h);
    hot.push_back({x, y, begin_ns + secondsToNs(noise_rng.exponential(config_.hot_pixel_rate_hz))});
  }
  stats.hot_pixels = static_cast<int>(hot.size());
  // Noise polarity: OFF when a uniform draw is below the OFF share (with share 0.5 the same draws as
  // a fair coin).
  const double off_share = 1.0 - config_.noise_on_fraction;
  const auto noisePolarity = [&] { return noise_rng.uniform() < off_share ? int8_t{-1} : int8_t{1}; };

  // Timestamp jitter: events wait in `pending` (sorted) until no later step can produce an earlier or
  // equal jittered time. A step [t_a, t_b] yields original times >= t_a (a crossing right at the start
  // rounds to t_a), so jittered times >= t_a - J with J the largest jitter; after the step ending at t_b,
  // every pending event before t_b - J is final.
  Random jitter_rng(seed_ ^ 0x4A49545445520000ULL);  // "JITTER"
  const int64_t sigma_j = config_.time_jitter_ns;
  const int64_t max_jitter = std::llround(3.0 * static_cast<double>(sigma_j));
  std::vector<Event> pending, ready;
  const auto deliver = [&](const std::vector<Event>& step, int64_t final_until) {
    if (sigma_j == 0) {
      if (!step.empty()) sink(step);
      return;
    }
    const std::size_t old_size = pending.size();
    for (Event e : step) {
      double z = jitter_rng.normal();
      while (std::fabs(z) > 3.0) z = jitter_rng.normal();  // truncated at 3σ
      e.t_ns = std::clamp<int64_t>(e.t_ns + std::llround(z * static_cast<double>(sigma_j)), begin_ns, end_ns);
      pending.push_back(e);
    }
    std::sort(pending.begin() + static_cast<std::ptrdiff_t>(old_size), pending.end(), eventLess);
    std::inplace_merge(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(old_size), pending.end(),
                       eventLess);
    const auto split = std::upper_bound(pending.begin(), pending.end(), final_until,
                                        [](int64_t t, const Event& e) { return t < e.t_ns; });
    if (split == pending.begin()) return;
    ready.assign(pending.begin(), split);
    pending.erase(pending.begin(), split);
    sink(ready);
  };

  std::vector<std::vector<Event>> buffers(static_cast<std::size_t>(threads));
  std::vector<uint64_t> drops(static_cast<std::size_t>(threads), 0);
  std::vector<Event> step_events;
  std::vector<Eigen::Vector2d> grid_pixels;
  std::vector<Eigen::Vector3d> grid_points;
  int64_t dt = config_.max_step_ns;
  int64_t t_a = begin_ns;
  stats.min_step_ns = INT64_MAX;
  while (t_a < end_ns) {
    // Adaptive step: project the points seen at t_a with the pose at t_a + dt; shrink dt until the
    // largest image motion is at most max_pixel_motion, grow it again when motion is slow.
    renderer_.sparseHits(pose_a, 6, grid_pixels, grid_points);
    double motion_px = 0;
    StampedPose pose_b;
    int64_t t_b = 0;
    for (int attempt = 0; attempt < 60; ++attempt) {
      t_b = std::min(end_ns, t_a + dt);
      pose_b = motion.pose(t_b);
      const Eigen::Matrix3d R_c_w = pose_b.q_w_c.toRotationMatrix().transpose();
      motion_px = 0;
      for (std::size_t k = 0; k < grid_points.size(); ++k) {
        const auto pixel = camera_.project(R_c_w * (grid_points[k] - pose_b.p_w_c));
        // A point that leaves the front of the camera counts as a large motion.
        motion_px = std::max(motion_px, pixel ? (*pixel - grid_pixels[k]).norm() : 1e9);
      }
      if (motion_px <= config_.max_pixel_motion || dt <= config_.min_step_ns) break;
      dt = std::max(config_.min_step_ns,
                    static_cast<int64_t>(static_cast<double>(dt) *
                                         std::max(0.1, 0.8 * config_.max_pixel_motion / motion_px)));
    }
    const int64_t step = t_b - t_a;

    // Render at t_b and generate events (rows split over threads; each thread owns its rows' state).
    const Renderer::Frame frame = renderer_.prepare(pose_b);
    const auto contrast_scale =
        static_cast<float>(contrastScale(0.5 * (durationSeconds(begin_ns, t_a) + durationSeconds(begin_ns, t_b))));
    if (threads == 1) {
      buffers[0].clear();
      processRows(frame, t_a, t_b, contrast_scale, 0, h, buffers[0], drops[0]);
    } else {
      std::vector<std::thread> workers;
      for (int k = 1; k < threads; ++k) {
        workers.emplace_back([&, k] {
          buffers[static_cast<std::size_t>(k)].clear();
          processRows(frame, t_a, t_b, contrast_scale, h * k / threads, h * (k + 1) / threads,
                      buffers[static_cast<std::size_t>(k)], drops[static_cast<std::size_t>(k)]);
        });
      }
      buffers[0].clear();
      processRows(frame, t_a, t_b, contrast_scale, 0, h / threads, buffers[0], drops[0]);
      for (std::thread& worker : workers) worker.join();
    }
    step_events.clear();
    for (const auto& b : buffers) step_events.insert(step_events.end(), b.begin(), b.end());
    const std::size_t signal_events = step_events.size();
    while (next_noise_ns <= t_b) {
      const auto x = static_cast<uint16_t>(noise_rng.uniform() * w);
      const auto y = static_cast<uint16_t>(noise_rng.uniform() * h);
      const int8_t p = noisePolarity();
      step_events.push_back(Event{next_noise_ns, x, y, p});
      next_noise_ns += std::max<int64_t>(1, secondsToNs(noise_rng.exponential(total_noise_rate)));
    }
    const std::size_t background_end = step_events.size();
    for (HotPixel& hp : hot) {
      while (hp.next_ns <= t_b) {
        step_events.push_back(Event{hp.next_ns, hp.x, hp.y, noisePolarity()});
        hp.next_ns += std::max<int64_t>(1, secondsToNs(noise_rng.exponential(config_.hot_pixel_rate_hz)));
      }
    }
    stats.background_events += background_end - signal_events;
    stats.hot_pixel_events += step_events.size() - background_end;
    stats.noise_events += step_events.size() - signal_events;
    std::sort(step_events.begin(), step_events.end(), eventLess);
    for (const Event& e : step_events) (e.polarity > 0 ? stats.on_events : stats.off_events) += 1;
    stats.events += step_events.size();
    deliver(step_events, t_b - max_jitter - 1);

    ++stats.render_steps;
    stats.min_step_ns = std::min(stats.min_step_ns, step);
    stats.max_step_ns = std::max(stats.max_step_ns, step);
    stats.max_step_motion_px = std::max(stats.max_step_motion_px, motion_px);
    while (frame_period_ns > 0 && next_frame_ns <= t_b) {
      emitFrame(next_frame_ns);
      next_frame_ns += frame_period_ns;
    }
    t_a = t_b;
    pose_a = pose_b;
    // Grow the next step when this one moved the image much less than allowed.
    if (motion_px < 0.5 * config_.max_pixel_motion) {
      const double grow = motion_px > 0 ? 0.8 * config_.max_pixel_motion / motion_px : 2.0;
      dt = std::min(config_.max_step_ns,
                    static_cast<int64_t>(static_cast<double>(dt) * std::min(2.0, grow)) + 1);
    }
  }
  if (!pending.empty()) sink(pending);  // the rest of the jittered events (already sorted)
  for (uint64_t d : drops) stats.refractory_drops += d;
  if (stats.render_steps == 0) stats.min_step_ns = 0;
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return stats;
}

}  // namespace asynevo::sim
