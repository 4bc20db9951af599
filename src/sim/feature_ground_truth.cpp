#include "asynevo/sim/feature_ground_truth.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

#include "asynevo/core/error.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/trajectory_io.hpp"

namespace asynevo::sim {

// ---- SampledMotion -----------------------------------------------------------------------------------

SampledMotion::SampledMotion(StampedTrajectory samples, std::string description)
    : samples_(std::move(samples)), description_(std::move(description)) {
  if (samples_.size() < 2) throw std::invalid_argument("a sampled motion needs at least two poses");
  for (std::size_t i = 1; i < samples_.size(); ++i) {
    if (samples_[i].t_ns < samples_[i - 1].t_ns)
      throw std::invalid_argument(fmt::format("pose times decrease at sample {}", i));
  }
}

StampedPose SampledMotion::pose(int64_t t_ns) const {
  if (t_ns <= samples_.front().t_ns) return samples_.front();
  if (t_ns >= samples_.back().t_ns) return samples_.back();
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t_ns,
                                   [](int64_t t, const StampedPose& p) { return t < p.t_ns; });
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  StampedPose out;
  out.t_ns = t_ns;
  if (b.t_ns == a.t_ns) return b;
  const double u = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  out.p_w_c = (1 - u) * a.p_w_c + u * b.p_w_c;
  out.q_w_c = a.q_w_c.slerp(u, b.q_w_c).normalized();
  return out;
}

// ---- FeatureGroundTruth ------------------------------------------------------------------------------

FeatureGroundTruth::FeatureGroundTruth(Scene scene, CameraModel camera, std::shared_ptr<const Motion> motion,
                                       const FeatureGroundTruthOptions& options)
    : scene_(std::move(scene)), camera_(std::move(camera)), motion_(std::move(motion)), options_(options) {
  if (!motion_) throw std::invalid_argument("feature ground truth needs a motion");
}

std::optional<double> FeatureGroundTruth::castRayNormalized(const StampedPose& T_w_c,
                                                            const Eigen::Vector3d& ray_c,
                                                            Eigen::Vector3d* p_w, int* plane_index) const {
  const Eigen::Vector3d d = T_w_c.q_w_c * ray_c;  // world direction; depth Z = s when ray_c.z() = 1
  const Eigen::Vector3d& o = T_w_c.p_w_c;
  double best = std::numeric_limits<double>::infinity();
  int best_plane = -1;
  for (std::size_t i = 0; i < scene_.planes.size(); ++i) {
    const TexturedPlane& plane = scene_.planes[i];
    const Eigen::Vector3d n = plane.normal();
    const double denom = n.dot(d);
    if (std::fabs(denom) < 1e-12) continue;
    const double s = n.dot(plane.center_w - o) / denom;
    if (!(s > 1e-6) || s >= best) continue;
    const Eigen::Vector3d q = o + s * d - plane.center_w;
    if (std::fabs(q.dot(plane.u_w)) > plane.half_width || std::fabs(q.dot(plane.v_w)) > plane.half_height)
      continue;
    best = s;
    best_plane = static_cast<int>(i);
  }
  if (!std::isfinite(best)) return std::nullopt;
  if (p_w) *p_w = o + best * d;
  if (plane_index) *plane_index = best_plane;
  return best * ray_c.z();
}

std::optional<double> FeatureGroundTruth::castRay(const StampedPose& T_w_c, const Eigen::Vector2d& pixel,
                                                  Eigen::Vector3d* p_w, int* plane) const {
  const std::optional<Eigen::Vector2d> xn = camera_.unproject(pixel);
  if (!xn) return std::nullopt;
  return castRayNormalized(T_w_c, Eigen::Vector3d(xn->x(), xn->y(), 1.0), p_w, plane);
}

FeatureGroundTruth::Anchor FeatureGroundTruth::anchor(int64_t t_ns, const Eigen::Vector2d& pixel) const {
  Anchor a;
  const StampedPose T_w_c = motion_->pose(t_ns);
  const std::optional<double> depth = castRay(T_w_c, pixel, &a.p_w, &a.plane);
  if (!depth) return a;
  a.valid = true;
  a.depth = *depth;
  // Depth discontinuity (or background) on a ring around the pixel.
  constexpr int kRing = 8;
  for (int k = 0; k < kRing; ++k) {
    const double angle = 2.0 * M_PI * k / kRing;
    const Eigen::Vector2d q =
        pixel + options_.edge_radius_px * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    const std::optional<double> dq = castRay(T_w_c, q);
    if (!dq || std::fabs(*dq - *depth) > options_.edge_relative_jump * *depth) {
      a.depth_edge = true;
      break;
    }
  }
  return a;
}

FeatureGroundTruth::Projection FeatureGroundTruth::project(const Eigen::Vector3d& p_w, int64_t t_ns) const {
  Projection out;
  const StampedPose T_w_c = motion_->pose(t_ns);
  const Eigen::Vector3d p_c = T_w_c.q_w_c.conjugate() * (p_w - T_w_c.p_w_c);
  const std::optional<Eigen::Vector2d> pixel = camera_.project(p_c, 1e-6);
  if (!pixel) return out;
  out.valid = true;
  out.pixel = *pixel;
  const std::optional<double> hit = castRayNormalized(T_w_c, p_c / p_c.z(), nullptr);
  out.occluded = hit && *hit < (1.0 - options_.occlusion_margin) * p_c.z();
  return out;
}

// ---- evaluation --------------------------------------------------------------------------------------

namespace {

/// Quantile by linear interpolation of the sorted values.
double quantile(const std::vector<double>& sorted, double f) {
  if (sorted.empty()) return 0;
  const double pos = f * static_cast<double>(sorted.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(pos));
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  const double w = pos - static_cast<double>(i);
  return (1 - w) * sorted[i] + w * sorted[j];
}

AccuracySummary summarize(const std::vector<const TrackAccuracy*>& tracks,
                          const FeatureAccuracyOptions& options) {
  AccuracySummary s;
  std::vector<double> errors, lifetimes;
  std::vector<double> along;
  for (const TrackAccuracy* t : tracks) {
    ++s.tracks;
    errors.insert(errors.end(), t->errors_px.begin(), t->errors_px.end());
    along.insert(along.end(), t->along_motion_px.begin(), t->along_motion_px.end());
    lifetimes.push_back(static_cast<double>(t->last_ns - t->first_ns) * 1e-9);
    if (t->first_bad_ns >= 0 && t->bad_survival_ns > options.max_bad_survival_ns) ++s.bad_tracks;
    s.worst_bad_survival_ns = std::max(s.worst_bad_survival_ns, t->bad_survival_ns);
  }
  std::sort(errors.begin(), errors.end());
  std::sort(lifetimes.begin(), lifetimes.end());
  s.measurements = errors.size();
  s.median_px = quantile(errors, 0.5);
  s.p90_px = quantile(errors, 0.9);
  s.p99_px = quantile(errors, 0.99);
  s.max_px = errors.empty() ? 0 : errors.back();
  const auto above = errors.end() - std::upper_bound(errors.begin(), errors.end(), options.bad_error_px);
  s.share_above_bad = errors.empty() ? 0 : static_cast<double>(above) / static_cast<double>(errors.size());
  std::sort(along.begin(), along.end());
  s.median_along_motion_px = quantile(along, 0.5);
  s.lifetime_median_s = quantile(lifetimes, 0.5);
  s.lifetime_p90_s = quantile(lifetimes, 0.9);
  return s;
}

std::string summaryLine(const char* label, const AccuracySummary& s, const FeatureAccuracyOptions& o) {
  return fmt::format(
      "{:<18}{} tracks, {} errors: median {:.3f} px, p90 {:.3f}, p99 {:.3f}, max {:.1f}, > {:g} px {:.2f} %; "
      "tracks with error > {:g} px surviving > {:g} ms: {} (worst {:.1f} ms); lifetime median {:.3f} s, "
      "p90 {:.3f} s; median error along the motion {:+.3f} px\n",
      label, s.tracks, s.measurements, s.median_px, s.p90_px, s.p99_px, s.max_px, o.bad_error_px,
      100 * s.share_above_bad, o.bad_error_px, static_cast<double>(o.max_bad_survival_ns) * 1e-6,
      s.bad_tracks, static_cast<double>(s.worst_bad_survival_ns) * 1e-6, s.lifetime_median_s,
      s.lifetime_p90_s, s.median_along_motion_px);
}

}  // namespace

std::string FeatureAccuracy::summary(const FeatureAccuracyOptions& options) const {
  std::string out = summaryLine("track error", all, options);
  out += summaryLine("  rigid anchors", rigid, options);
  out += fmt::format(
      "                  {} tracks anchored at a depth discontinuity, {} occluded measurements, {} tracks "
      "unanchored, {} with < {} measurements\n",
      depth_edge_tracks, occluded_measurements, unanchored_tracks, short_tracks, options.min_measurements);
  return out;
}

FeatureAccuracy evaluateFeatureTracks(const std::vector<TrackMeasurement>& measurements,
                                      const FeatureGroundTruth& ground_truth,
                                      const FeatureAccuracyOptions& options) {
  std::map<int64_t, std::vector<const TrackMeasurement*>> by_id;
  for (const TrackMeasurement& m : measurements) by_id[m.feature_id].push_back(&m);
  FeatureAccuracy result;
  for (auto& [id, ms] : by_id) {
    std::stable_sort(ms.begin(), ms.end(),
                     [](const TrackMeasurement* a, const TrackMeasurement* b) { return a->t_ns < b->t_ns; });
    TrackAccuracy t;
    t.id = id;
    t.first_ns = ms.front()->t_ns;
    t.last_ns = ms.back()->t_ns;
    t.measurements = static_cast<int>(ms.size());
    const FeatureGroundTruth::Anchor a =
        ground_truth.anchor(t.first_ns + options.time_offset_ns, Eigen::Vector2d(ms.front()->x, ms.front()->y));
    t.anchored = a.valid;
    t.depth_edge = a.depth_edge;
    t.plane = a.plane;
    if (a.valid) {
      for (std::size_t i = 1; i < ms.size(); ++i) {
        const int64_t t_true = ms[i]->t_ns + options.time_offset_ns;
        const FeatureGroundTruth::Projection p = ground_truth.project(a.p_w, t_true);
        const double e = p.valid ? (p.pixel - Eigen::Vector2d(ms[i]->x, ms[i]->y)).norm()
                                 : std::numeric_limits<double>::infinity();
        t.errors_px.push_back(e);
        t.ages_s.push_back(1e-9 * double(ms[i]->t_ns - t.first_ns));
        if (p.valid) {
          // Direction of the image motion from the projections 1 ms either side.
          constexpr int64_t kHalfStep = 1'000'000;
          const FeatureGroundTruth::Projection before = ground_truth.project(a.p_w, t_true - kHalfStep);
          const FeatureGroundTruth::Projection after = ground_truth.project(a.p_w, t_true + kHalfStep);
          const Eigen::Vector2d motion = after.pixel - before.pixel;
          if (before.valid && after.valid && motion.norm() > 2e-3)  // > 1 px/s
            t.along_motion_px.push_back(
                (Eigen::Vector2d(ms[i]->x, ms[i]->y) - p.pixel).dot(motion.normalized()));
        }
        t.occluded += p.occluded ? 1 : 0;
        t.max_error_px = std::max(t.max_error_px, e);
        if (e > options.bad_error_px && t.first_bad_ns < 0) t.first_bad_ns = ms[i]->t_ns;
      }
      if (t.first_bad_ns >= 0) t.bad_survival_ns = t.last_ns - t.first_bad_ns;
      std::vector<double> sorted = t.errors_px;
      std::sort(sorted.begin(), sorted.end());
      t.median_error_px = quantile(sorted, 0.5);
    }
    result.tracks.push_back(std::move(t));
  }
  std::vector<const TrackAccuracy*> all, rigid;
  for (const TrackAccuracy& t : result.tracks) {
    if (!t.anchored) {
      ++result.unanchored_tracks;
      continue;
    }
    if (t.measurements < options.min_measurements) {
      ++result.short_tracks;
      continue;
    }
    all.push_back(&t);
    result.occluded_measurements += static_cast<uint64_t>(t.occluded);
    if (t.depth_edge) {
      ++result.depth_edge_tracks;
    } else {
      rigid.push_back(&t);
    }
  }
  result.all = summarize(all, options);
  result.rigid = summarize(rigid, options);
  return result;
}

// ---- simulated folders ---------------------------------------------------------------------------

bool isSimulatedDataset(const std::string& dir) {
  const std::filesystem::path d(dir);
  return std::filesystem::is_regular_file(d / "sim.yaml") &&
         std::filesystem::is_regular_file(d / "groundtruth.txt");
}

FeatureGroundTruth loadSimulatedGroundTruth(const std::string& dir) {
  const std::filesystem::path d(dir);
  const std::string meta_path = (d / "sim.yaml").string();
  if (!std::filesystem::is_regular_file(meta_path))
    throw InputError(meta_path, "no such file: not a folder written by 'asynevo simulate'");
  YAML::Node meta;
  try {
    meta = YAML::LoadFile(meta_path);
  } catch (const YAML::ParserException& e) {
    throw InputError::atLine(meta_path, static_cast<uint64_t>(e.mark.line) + 1, e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(meta_path, e.what());
  }
  std::string scene_name;
  uint64_t seed = 0;
  try {
    if (!meta["scene"]) throw InputError(meta_path, "missing key 'scene'");
    if (!meta["seed"]) throw InputError(meta_path, "missing key 'seed'");
    scene_name = meta["scene"].as<std::string>();
    seed = meta["seed"].as<uint64_t>();
  } catch (const YAML::Exception& e) {
    throw InputError::atLine(meta_path, static_cast<uint64_t>(e.mark.line) + 1,
                             "'scene' must be a string and 'seed' an integer");
  }

  const std::string gt_path = (d / "groundtruth.txt").string();
  if (!std::filesystem::is_regular_file(gt_path)) throw InputError(gt_path, "no such file");
  StampedTrajectory gt = readTumTrajectory(gt_path);
  if (gt.size() < 2) throw InputError(gt_path, "fewer than two poses");
  auto motion = std::make_shared<SampledMotion>(std::move(gt), "ground truth of " + dir);

  const std::filesystem::path camchain = d / "camchain.yaml", calib = d / "calib.txt";
  CameraModel camera = std::filesystem::is_regular_file(camchain) ? readKalibrCalibration(camchain.string())
                       : std::filesystem::is_regular_file(calib)
                           ? readEcdCalibration(calib.string())
                           : throw InputError(dir, "no camchain.yaml or calib.txt");

  Scene scene;
  if (isBuiltinScene(scene_name)) {
    scene = makeBuiltinScene(scene_name, *motion, camera, seed);
  } else if (std::filesystem::is_regular_file(scene_name)) {
    scene = loadSceneFile(scene_name, *motion, camera, seed);
  } else {
    throw InputError(meta_path,
                     fmt::format("scene '{}' is neither built-in nor an existing scene file", scene_name));
  }
  return FeatureGroundTruth(std::move(scene), std::move(camera), std::move(motion));
}

}  // namespace asynevo::sim
