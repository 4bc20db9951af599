#include "asynevo/sim/motion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/lie/so3.hpp"
#include "asynevo/sim/speed_ramp.hpp"

namespace asynevo::sim {

namespace {

constexpr double kTwoPi = 6.283185307179586;

Eigen::Quaterniond expQ(const Eigen::Vector3d& phi) { return lie::so3::expQuaternion(phi); }
Eigen::Vector3d logQ(const Eigen::Quaterniond& q) { return lie::so3::log(q); }

// ---- presets ---------------------------------------------------------------------------------------
// Sums of sinusoids with incommensurate frequencies, so the motion does not repeat within a sequence and
// excites every axis. Peak rates are given next to each preset (docs/simulator.md).

Eigen::Vector3d rotationAngles(double t, double scale) {
  return scale * Eigen::Vector3d(0.30 * std::sin(kTwoPi * 0.31 * t), 0.40 * std::sin(kTwoPi * 0.23 * t + 0.5),
                                 0.20 * std::sin(kTwoPi * 0.17 * t + 1.0));
}

Eigen::Vector3d translationOffsets(double t, double scale) {
  return scale * Eigen::Vector3d(0.25 * std::sin(kTwoPi * 0.40 * t), 0.15 * std::sin(kTwoPi * 0.29 * t + 0.7),
                                 0.15 * std::sin(kTwoPi * 0.19 * t + 1.3));
}

}  // namespace

AnalyticMotion::AnalyticMotion(std::string description, int64_t begin_ns, int64_t end_ns, Function function)
    : description_(std::move(description)),
      begin_ns_(begin_ns),
      end_ns_(end_ns),
      function_(std::move(function)) {
  if (end_ns_ < begin_ns_) throw std::invalid_argument("motion ends before it begins");
}

StampedPose AnalyticMotion::pose(int64_t t_ns) const {
  StampedPose pose;
  pose.t_ns = std::clamp(t_ns, begin_ns_, end_ns_);
  function_(durationSeconds(begin_ns_, pose.t_ns), pose.p_w_c, pose.q_w_c);
  pose.q_w_c.normalize();
  return pose;
}

std::vector<std::string> motionPresetNames() {
  return {"static", "rotation", "rotation-dominated", "translation", "6dof", "fast-translation", "slow-start", "speed-ramp"};
}

bool isMotionPreset(const std::string& name) {
  const auto names = motionPresetNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

namespace {

using V = Eigen::Vector3d;
using Q = Eigen::Quaterniond;

// slow-start: still for kStillS, then the time warp τ(t) with τ' rising from 0 to 1 over kRampS along
// the quintic smootherstep 6x⁵ − 15x⁴ + 10x³ (so pose, velocity and acceleration stay continuous), then
// τ' = 1: the 6dof preset at τ. Its integral: kRampS (x⁶ − 3x⁵ + 2.5x⁴), which is kRampS/2 at x = 1.
constexpr double kStillS = 1.5;
constexpr double kRampS = 1.0;

double slowStartWarp(double t) {
  if (t <= kStillS) return 0.0;
  const double x = (t - kStillS) / kRampS;
  if (x < 1.0) return kRampS * x * x * x * x * (x * x - 3 * x + 2.5);
  return kRampS * 0.5 + (t - kStillS - kRampS);
}

/// The preset's pose as a function of the time since its phase 0, and its description.
std::pair<AnalyticMotion::Function, std::string> presetFunction(const std::string& name) {
  if (name == "static") {
    return {[](double, V& p, Q& q) {
              p.setZero();
              q.setIdentity();
            },
            "preset static (camera at rest)"};
  }
  if (name == "rotation") {
    // Peak angular rate ~0.9 rad/s, rotation up to ~0.5 rad about each axis; no translation.
    return {[](double t, V& p, Q& q) {
              p.setZero();
              q = expQ(rotationAngles(t, 1.0));
            },
            "preset rotation"};
  }
  if (name == "rotation-dominated") {
    // The rotation preset plus 15 % of the translation preset (peak ~0.1 m/s, as ECD shapes_rotation):
    // a monocular start is possible only where the translation builds up parallax, and the path is long
    // enough for a Sim(3) alignment (a pure rotation has none).
    return {[](double t, V& p, Q& q) {
              p = translationOffsets(t, 0.15);
              q = expQ(rotationAngles(t, 1.0));
            },
            "preset rotation-dominated"};
  }
  if (name == "translation") {
    // Peak speed ~0.7 m/s (x), no rotation.
    return {[](double t, V& p, Q& q) {
              p = translationOffsets(t, 1.0);
              q.setIdentity();
            },
            "preset translation"};
  }
  if (name == "6dof") {
    // Both, at 70 % of the single-mode amplitudes.
    return {[](double t, V& p, Q& q) {
              p = translationOffsets(t, 0.7);
              q = expQ(rotationAngles(t, 0.7));
            },
            "preset 6dof"};
  }
  if (name == "fast-translation") {
    // Side to side along x at up to ~1.9 m/s (0.3 m amplitude, 1 Hz), for the high-speed experiments.
    return {[](double t, V& p, Q& q) {
              p = V(0.3 * std::sin(kTwoPi * 1.0 * t), 0.0, 0.0);
              q.setIdentity();
            },
            "preset fast-translation"};
  }
  if (name == "speed-ramp") {
    // Along x (parallel to a wall in front): 1.4 m/s for 2 s, a 1.5 s smootherstep to 9 m/s, then 9 m/s
    // (sim/speed_ramp.hpp; the repeated-texture experiment, docs/results/repeated_texture.md).
    return {[](double t, V& p, Q& q) {
              p = V(SpeedRamp{}.distance(t), 0.0, 0.0);
              q.setIdentity();
            },
            "preset speed-ramp (along x: 1.4 m/s for 2 s, 1.5 s ramp to 9 m/s, then 9 m/s)"};
  }
  if (name == "slow-start") {
    // Nearly still for 1.5 s (a 0.2 mm / 0.1 mrad drift, far below a pixel), then a 1 s ramp into 6dof.
    return {[](double t, V& p, Q& q) {
              const double tau = slowStartWarp(t);
              const V drift_p = 2e-4 * V(std::sin(kTwoPi * 0.13 * t), std::sin(kTwoPi * 0.21 * t + 1.0),
                                         std::sin(kTwoPi * 0.17 * t + 2.0));
              const V drift_r = 1e-4 * V(std::sin(kTwoPi * 0.11 * t + 0.3), std::sin(kTwoPi * 0.19 * t + 1.1),
                                         std::sin(kTwoPi * 0.23 * t + 2.2));
              p = translationOffsets(tau, 0.7) + drift_p;
              q = expQ(rotationAngles(tau, 0.7)) * expQ(drift_r);
            },
            "preset slow-start (still 1.5 s with a 0.2 mm drift, 1 s ramp into 6dof)"};
  }
  throw std::invalid_argument(
      fmt::format("unknown motion preset '{}' (presets: {})", name, fmt::join(motionPresetNames(), ", ")));
}

}  // namespace

std::unique_ptr<Motion> makePresetMotion(const std::string& name, double duration_s, double start_s) {
  if (!(duration_s > 0) || !std::isfinite(duration_s)) {
    throw std::invalid_argument(fmt::format("duration must be positive, got {}", duration_s));
  }
  if (!(start_s >= 0) || !std::isfinite(start_s)) {
    throw std::invalid_argument(fmt::format("--start must not be negative, got {}", start_s));
  }
  const int64_t end_ns = secondsToNs(duration_s);
  auto [function, description] = presetFunction(name);
  if (start_s == 0) return std::make_unique<AnalyticMotion>(description, 0, end_ns, function);
  // Phase shift by start_s, re-based so the first pose is the preset's pose at phase 0:
  //   T(t) = T_f(0) T_f(S)⁻¹ T_f(t + S).
  V p0, pS;
  Q q0, qS;
  function(0.0, p0, q0);
  function(start_s, pS, qS);
  q0.normalize();
  qS.normalize();
  const Q q_rebase = q0 * qS.conjugate();
  const V p_rebase = p0 - q_rebase * pS;
  return std::make_unique<AnalyticMotion>(
      fmt::format("{} from {} s", description, start_s), 0, end_ns,
      [function = function, q_rebase, p_rebase, start_s](double t, V& p, Q& q) {
        V pt;
        Q qt;
        function(t + start_s, pt, qt);
        p = p_rebase + q_rebase * pt;
        q = q_rebase * qt.normalized();
      });
}

// ---- spline motion ----------------------------------------------------------------------------------

SplineMotion::SplineMotion(const StampedTrajectory& samples_in, const MotionFileOptions& options,
                           std::string description)
    : description_(std::move(description)) {
  if (!(options.sample_dt_s > 0)) throw std::invalid_argument("sample_dt_s must be positive");
  if (options.cutoff_hz < 0) throw std::invalid_argument("cutoff_hz must not be negative");
  // Gaussian kernel with -3 dB at the cut-off: |H(f)| = exp(-2π²σ²f²) = 1/√2  =>  σ = √(ln 2) / (2π f_c).
  const double sigma_s =
      options.cutoff_hz > 0 ? std::sqrt(std::log(2.0)) / (kTwoPi * options.cutoff_hz) : 0.0;
  const int64_t margin_ns = secondsToNs(3 * sigma_s);

  // Unique times inside the window (plus a margin for the filter), continuous quaternion signs.
  StampedTrajectory samples;
  // Saturating window bounds (the defaults are INT64_MIN / INT64_MAX).
  const int64_t lo = options.begin_ns < INT64_MIN + margin_ns ? INT64_MIN : options.begin_ns - margin_ns;
  const int64_t hi = options.end_ns > INT64_MAX - margin_ns ? INT64_MAX : options.end_ns + margin_ns;
  for (const StampedPose& s : samples_in) {
    if (s.t_ns < lo || s.t_ns > hi) continue;
    if (!samples.empty() && s.t_ns <= samples.back().t_ns) continue;
    StampedPose copy = s;
    copy.p_w_c *= options.position_scale;
    copy.q_w_c.normalize();
    if (!samples.empty() && copy.q_w_c.dot(samples.back().q_w_c) < 0) copy.q_w_c.coeffs() *= -1;
    samples.push_back(copy);
  }
  if (samples.size() < 2) throw std::invalid_argument("a motion needs at least two poses in its time window");

  const int64_t first_ns = samples.front().t_ns;
  const int64_t last_ns = samples.back().t_ns;
  begin_ns_ = std::max(first_ns, options.begin_ns);
  end_ns_ = std::min(last_ns, options.end_ns);
  if (end_ns_ <= begin_ns_) throw std::invalid_argument("the motion's time window is empty");
  knot_dt_ns_ = std::max<int64_t>(1, secondsToNs(options.sample_dt_s));

  // 1. Resample on a uniform grid τ_k = first + k Δ (linear position, slerp rotation).
  const auto n = static_cast<std::size_t>((last_ns - first_ns) / knot_dt_ns_) + 1;
  std::vector<Eigen::Vector3d> p(n);
  std::vector<Eigen::Quaterniond> q(n);
  std::size_t j = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const int64_t t = first_ns + static_cast<int64_t>(k) * knot_dt_ns_;
    while (j + 2 < samples.size() && samples[j + 1].t_ns < t) ++j;
    const StampedPose& a = samples[j];
    const StampedPose& b = samples[j + 1];
    const double u =
        std::clamp(static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns), 0.0, 1.0);
    p[k] = (1 - u) * a.p_w_c + u * b.p_w_c;
    q[k] = a.q_w_c.slerp(u, b.q_w_c);
  }

  // 2. Gaussian low-pass: positions averaged, rotations averaged in the tangent space at the centre
  //    sample (one Gauss-Newton step of the weighted Karcher mean). The kernel is truncated at 3σ and
  //    renormalized near the ends.
  if (sigma_s > 0) {
    const double sigma_k = sigma_s / options.sample_dt_s;
    const int half = static_cast<int>(std::ceil(3 * sigma_k));
    std::vector<double> w(static_cast<std::size_t>(half) + 1);
    for (int d = 0; d <= half; ++d)
      w[static_cast<std::size_t>(d)] = std::exp(-0.5 * d * d / (sigma_k * sigma_k));
    std::vector<Eigen::Vector3d> ps(n);
    std::vector<Eigen::Quaterniond> qs(n);
    for (std::size_t k = 0; k < n; ++k) {
      Eigen::Vector3d sum_p = Eigen::Vector3d::Zero();
      Eigen::Vector3d sum_phi = Eigen::Vector3d::Zero();
      double sum_w = 0;
      const Eigen::Quaterniond q_inv = q[k].conjugate();
      for (int d = -half; d <= half; ++d) {
        const auto i = static_cast<std::ptrdiff_t>(k) + d;
        if (i < 0 || i >= static_cast<std::ptrdiff_t>(n)) continue;
        const double wd = w[static_cast<std::size_t>(std::abs(d))];
        sum_p += wd * p[static_cast<std::size_t>(i)];
        sum_phi += wd * logQ(q_inv * q[static_cast<std::size_t>(i)]);
        sum_w += wd;
      }
      ps[k] = sum_p / sum_w;
      qs[k] = (q[k] * expQ(sum_phi / sum_w)).normalized();
    }
    p.swap(ps);
    q.swap(qs);
  }

  // 3. Control points: the smoothed samples, padded at both ends by reflection (c_{-1} = 2 s_0 - s_1),
  //    so the spline at τ_k is (s_{k-1} + 4 s_k + s_{k+1}) / 6 and the domain covers [τ_0, τ_{n-1}].
  const auto reflectP = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) -> Eigen::Vector3d {
    return 2 * a - b;
  };
  const auto reflectQ = [](const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    return (a * expQ(-logQ(a.conjugate() * b))).normalized();
  };
  const Eigen::Quaterniond q_before = n > 1 ? reflectQ(q[0], q[1]) : q[0];
  const Eigen::Quaterniond q_after = n > 1 ? reflectQ(q[n - 1], q[n - 2]) : q[n - 1];
  positions_.push_back(n > 1 ? reflectP(p[0], p[1]) : p[0]);
  rotations_.push_back(q_before);
  for (std::size_t k = 0; k < n; ++k) {
    positions_.push_back(p[k]);
    rotations_.push_back(q[k]);
  }
  positions_.push_back(n > 1 ? reflectP(p[n - 1], p[n - 2]) : p[n - 1]);
  rotations_.push_back(q_after);
  // One more of each so the segment that starts at τ_{n-1} is complete.
  positions_.push_back(positions_.back());
  rotations_.push_back(rotations_.back());
  for (std::size_t k = 0; k + 1 < rotations_.size(); ++k) {
    if (rotations_[k + 1].dot(rotations_[k]) < 0) rotations_[k + 1].coeffs() *= -1;
    rotation_deltas_.push_back(logQ(rotations_[k].conjugate() * rotations_[k + 1]));
  }
  // The spline's domain is [τ_0, τ_{n-1}]; it may extend past the last sample by < Δ.
  end_ns_ = std::min(end_ns_, first_ns + static_cast<int64_t>(n - 1) * knot_dt_ns_);
  begin_ns_ = std::max(begin_ns_, first_ns);
  if (end_ns_ <= begin_ns_)
    throw std::invalid_argument("the motion's time window is shorter than one sample step");
  // Remember where the grid starts: τ_0 = first sample.
  grid_origin_ns_ = first_ns;
}

StampedPose SplineMotion::pose(int64_t t_ns) const {
  StampedPose out;
  out.t_ns = std::clamp(t_ns, begin_ns_, end_ns_);
  const int64_t rel = out.t_ns - grid_origin_ns_;
  auto i = static_cast<std::size_t>(rel / knot_dt_ns_);
  double u =
      static_cast<double>(rel - static_cast<int64_t>(i) * knot_dt_ns_) / static_cast<double>(knot_dt_ns_);
  // Segment i (t in [τ_i, τ_{i+1})) uses control points c_i .. c_{i+3} = s_{i-1} .. s_{i+2}.
  if (i + 3 >= positions_.size()) {
    i = positions_.size() - 4;
    u = 1.0;
  }
  const double u2 = u * u;
  const double u3 = u2 * u;
  const double b1 = (5 + 3 * u - 3 * u2 + u3) / 6;
  const double b2 = (1 + 3 * u + 3 * u2 - 2 * u3) / 6;
  const double b3 = u3 / 6;
  out.p_w_c = positions_[i] + b1 * (positions_[i + 1] - positions_[i]) +
              b2 * (positions_[i + 2] - positions_[i + 1]) + b3 * (positions_[i + 3] - positions_[i + 2]);
  out.q_w_c = (rotations_[i] * expQ(b1 * rotation_deltas_[i]) * expQ(b2 * rotation_deltas_[i + 1]) *
               expQ(b3 * rotation_deltas_[i + 2]))
                  .normalized();
  return out;
}

std::unique_ptr<Motion> loadMotionFile(const std::string& path, const MotionFileOptions& options) {
  const StampedTrajectory samples = readTumTrajectory(path);
  std::string description = fmt::format("file {} (cut-off {} Hz, knots every {} ms, position scale {})", path,
                                        options.cutoff_hz, options.sample_dt_s * 1e3, options.position_scale);
  try {
    return std::make_unique<SplineMotion>(samples, options, std::move(description));
  } catch (const std::invalid_argument& e) {
    throw InputError(path, e.what());
  }
}

StampedTrajectory sampleMotion(const Motion& motion, int64_t dt_ns) {
  StampedTrajectory out;
  if (dt_ns <= 0) throw std::invalid_argument("sampling interval must be positive");
  for (int64_t t = motion.beginNs(); t < motion.endNs(); t += dt_ns) out.push_back(motion.pose(t));
  out.push_back(motion.pose(motion.endNs()));
  return out;
}

}  // namespace asynevo::sim
