// frontend_eval: runs the frontend on ECD-style rotation slices and reports the rotation-consistency
// accuracy (rotation_check.hpp), track lifetimes, the fitted angular velocity next to motion.txt (gyro)
// and groundtruth.txt (mocap, over the whole slice), and the frontend statistics. On simulated data
// (--sim: simulated in memory; a folder written by 'asynevo simulate') it reports the error of every
// track against the exact feature ground truth (sim/feature_ground_truth.hpp).
//
//   frontend_eval [--yaml 'frontend: {min_dt_ms: 1}'] [--accel] [--tracks FILE] [--ends FILE] DIR...
//   frontend_eval [--yaml ...] [--worst N] --sim SCENE:MOTION:SECONDS[:SEED] ...   e.g. --sim shapes:6dof:2
//   frontend_eval --synthetic
// DIR is any dataset folder (events.aevt, events.txt, ...; docs/reference/formats.md).
// --time-offset-ms MS: simulated data: each measurement compared with the truth MS later (the tracker's
// effective delay is the offset with the smallest error; docs/results/track_errors.md).
// --ends FILE: DIR: every feature's end, `id t reason measurements` per line (reasons as in stats.json).
// --corners FILE: DIR: every corner event of the detector run over all events, `t x y score` per line.
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/frontend/corner_detector.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/frontend/rotation_check.hpp"
#include "asynevo/frontend/sae.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/event_reader.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/sim/feature_ground_truth.hpp"
#include "frontend_run.hpp"
#include "sim_sequence.hpp"

using namespace asynevo;

namespace {

Eigen::Vector3d mocapAngularVelocity(const std::string& path, int64_t t0, int64_t t1) {
  const StampedTrajectory gt = readEcdGroundTruth(path);
  auto nearest = [&](int64_t t) {
    std::size_t best = 0;
    for (std::size_t i = 0; i < gt.size(); ++i)
      if (std::llabs(gt[i].t_ns - t) < std::llabs(gt[best].t_ns - t)) best = i;
    return gt[best];
  };
  const StampedPose a = nearest(t0), b = nearest(t1);
  const Eigen::AngleAxisd aa(a.q_w_c.conjugate() * b.q_w_c);
  return aa.axis() * aa.angle() / (static_cast<double>(b.t_ns - a.t_ns) * 1e-9);
}

// Tracking error against the exact motion of the synthetic stream (frontend_run.hpp).
void evaluateSynthetic(const Config& config) {
  const double speed = 500.0;
  const std::vector<Event> events = bench::syntheticStream(240, 180, 1.5, speed);
  const bench::FrontendRun run = bench::runFrontend(config.frontend, events, 240, 180);
  fmt::print("== synthetic stream ({} events)\n{}", events.size(), run.stats.summary());
  const bench::SyntheticAccuracy r = bench::evaluateSyntheticTracks(run.out.measurements, speed);
  using Q = bench::SyntheticAccuracy;
  fmt::print(
      "track error px    median {:.3f}  p90 {:.3f}  >5px {:.1f} %  over {} measurements of {} tracks\n",
      Q::quantile(r.errors_px, 0.5), Q::quantile(r.errors_px, 0.9), 100 * r.shareAbove(5.0), r.errors_px.size(),
      r.tracks_used);
  fmt::print("bad tracks        {} with error > 5 px surviving > 20 ms after it\n", r.bad_tracks);
  fmt::print("lifetime s        median {:.4f}  p90 {:.4f}\n", Q::quantile(r.lifetimes_s, 0.5),
             Q::quantile(r.lifetimes_s, 0.9));
}

// Median error by the measurement's age (time since the track's first measurement), rigid anchors only:
// how the error grows over a track's life (docs/frontend.md, "Why the error grows with age").
void printErrorByAge(const sim::FeatureAccuracy& r) {
  constexpr double kAgeEdges[] = {0.0, 0.01, 0.025, 0.05, 0.1, 0.2, 0.5, 1e9};
  constexpr int kAgeBins = static_cast<int>(std::size(kAgeEdges)) - 1;
  std::vector<std::vector<double>> by_age(kAgeBins);
  for (const auto& t : r.tracks) {
    if (!t.anchored || t.depth_edge) continue;
    for (std::size_t k = 0; k < t.errors_px.size(); ++k) {
      int bin = 0;
      while (bin + 1 < kAgeBins && t.ages_s[k] >= kAgeEdges[bin + 1]) ++bin;
      by_age[static_cast<std::size_t>(bin)].push_back(t.errors_px[k]);
    }
  }
  std::string ages;
  for (int bin = 0; bin < kAgeBins; ++bin) {
    auto& v = by_age[static_cast<std::size_t>(bin)];
    if (v.empty()) continue;
    std::sort(v.begin(), v.end());
    const bool last = bin + 1 == kAgeBins;  // labelled by its lower edge, the others by their upper one
    ages += fmt::format("  {} {:g} ms: {:.3f} ({})", last ? ">=" : "<", 1e3 * kAgeEdges[last ? bin : bin + 1],
                        v[v.size() / 2], v.size());
  }
  fmt::print("  error by age    median px (measurements), rigid anchors:{}\n", ages);
}

void printAccuracy(const std::vector<TrackMeasurement>& measurements, const sim::FeatureGroundTruth& gt,
                   int worst, const sim::FeatureAccuracyOptions& accuracy) {
  const sim::FeatureAccuracy r = sim::evaluateFeatureTracks(measurements, gt, accuracy);
  fmt::print("{}", r.summary());
  // Per texture of the anchor planes: median error, bad tracks.
  std::map<std::string, std::pair<std::vector<double>, std::pair<int, int>>> per_texture;
  for (const auto& t : r.tracks) {
    if (!t.anchored || t.errors_px.empty()) continue;
    const auto& plane = gt.scene().planes[static_cast<std::size_t>(t.plane)];
    auto& entry = per_texture[plane.texture ? plane.texture->description().substr(0, 24) : plane.name];
    entry.first.insert(entry.first.end(), t.errors_px.begin(), t.errors_px.end());
    ++entry.second.first;
    entry.second.second += t.bad_survival_ns > 20'000'000 ? 1 : 0;
  }
  for (auto& [name, entry] : per_texture) {
    std::sort(entry.first.begin(), entry.first.end());
    fmt::print("  on {:<26} {:4d} tracks, median {:.3f} px, p90 {:.3f}, bad tracks {}\n", name,
               entry.second.first, entry.first[entry.first.size() / 2],
               entry.first[entry.first.size() * 9 / 10], entry.second.second);
  }
  printErrorByAge(r);
  if (worst <= 0) return;
  std::vector<const sim::TrackAccuracy*> order;
  for (const auto& t : r.tracks)
    if (t.anchored && !t.errors_px.empty()) order.push_back(&t);
  std::sort(order.begin(), order.end(), [](const sim::TrackAccuracy* a, const sim::TrackAccuracy* b) {
    return a->bad_survival_ns != b->bad_survival_ns ? a->bad_survival_ns > b->bad_survival_ns
                                                    : a->max_error_px > b->max_error_px;
  });
  for (int i = 0; i < worst && i < static_cast<int>(order.size()); ++i) {
    const sim::TrackAccuracy& t = *order[static_cast<std::size_t>(i)];
    std::string errors;
    for (double e : t.errors_px) errors += fmt::format(" {:.1f}", e);
    fmt::print(
        "  id {:5d} plane {:2d} t {:.4f}..{:.4f} n {:3d} edge {} occl {} bad-survival {:.1f} ms max "
        "{:.2f}:{}\n",
        t.id, t.plane, t.first_ns * 1e-9, t.last_ns * 1e-9, t.measurements, t.depth_edge ? 1 : 0, t.occluded,
        t.bad_survival_ns * 1e-6, t.max_error_px, errors);
  }
}

// Why features end and what it costs: per drop reason, how many ended, how many of them were wrong when
// they ended (last error > 3 px), and how many were replaced by a new feature starting within 3 px of the
// ended one's last position within 50 ms (churn: the same place tracked again from scratch).
void printEndings(const frontend::MeasurementCollector& out, const sim::FeatureAccuracy& r) {
  struct Span {
    int64_t first_ns, last_ns;
    float x0, y0, x1, y1;
  };
  std::map<int64_t, Span> spans;
  for (const auto& m : out.measurements) {
    auto [it, inserted] = spans.try_emplace(m.feature_id, Span{m.t_ns, m.t_ns, m.x, m.y, m.x, m.y});
    if (!inserted) it->second = Span{it->second.first_ns, m.t_ns, it->second.x0, it->second.y0, m.x, m.y};
  }
  std::map<int64_t, double> last_error;
  for (const auto& t : r.tracks)
    if (t.anchored && !t.errors_px.empty()) last_error[t.id] = t.errors_px.back();
  struct Count {
    int ended = 0, wrong = 0, evaluated = 0, replaced = 0;
  };
  std::map<std::string, Count> counts;
  for (const auto& end : out.ends) {
    Count& c = counts[frontend::dropReasonName(end.reason)];
    ++c.ended;
    if (auto e = last_error.find(end.feature_id); e != last_error.end()) {
      ++c.evaluated;
      c.wrong += e->second > 3.0 ? 1 : 0;
    }
    const auto self = spans.find(end.feature_id);
    if (self == spans.end()) continue;
    for (auto it = spans.upper_bound(end.feature_id); it != spans.end(); ++it) {
      const Span& o = it->second;
      if (o.first_ns < end.t_ns || o.first_ns > end.t_ns + 50'000'000) continue;
      if (std::hypot(o.x0 - self->second.x1, o.y0 - self->second.y1) < 3.f) {
        ++c.replaced;
        break;
      }
    }
  }
  fmt::print("endings           reason: ended / last error > 3 px (of evaluated) / re-seeded within 3 px, 50 ms\n");
  for (const auto& [name, c] : counts)
    fmt::print("  {:<14} {:4d} / {:4d} (of {:4d}) / {:4d}\n", name, c.ended, c.wrong, c.evaluated, c.replaced);
}

void evaluateSimulated(const Config& config, const std::string& spec, int worst,
                       const sim::FeatureAccuracyOptions& accuracy) {
  // SCENE:MOTION:SECONDS[:SEED]
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t colon; (colon = spec.find(':', start)) != std::string::npos; start = colon + 1)
    parts.push_back(spec.substr(start, colon - start));
  parts.push_back(spec.substr(start));
  if (parts.size() < 3 || parts.size() > 4)
    throw std::invalid_argument("--sim takes SCENE:MOTION:SECONDS[:SEED], got " + spec);
  const uint64_t seed = parts.size() == 4 ? std::stoull(parts[3]) : 1;
  const bench::SimSequence s = bench::simulateSequence(parts[0], parts[1], std::stod(parts[2]), seed);
  const bench::FrontendRun run = bench::runFrontend(config.frontend, s.events, s.camera);
  const frontend::MeasurementCollector& out = run.out;
  fmt::print("== simulated {} ({:.2f} s, seed {}, {} events)\n{}", s.name, std::stod(parts[2]), seed,
             s.events.size(), run.stats.summary());
  printAccuracy(out.measurements, *s.ground_truth, worst, accuracy);
  printEndings(out, sim::evaluateFeatureTracks(out.measurements, *s.ground_truth, accuracy));
}

// Every corner event of the frontend's detector run over all events (the frontend itself detects only
// on events no tracker took), fixed threshold: `t x y score` per line (--corners FILE).
void writeCorners(const Config& config, const std::vector<Event>& events, int width, int height,
                  const std::string& path) {
  frontend::SurfaceOfActiveEvents sae(width, height, std::llround(config.frontend.refractory_period_ms * 1e6));
  frontend::CornerDetector detector(sae, frontend::Frontend::detectorParams(config.frontend));
  std::ofstream out(path);
  out << "# t x y score  (every corner event of the configured detector)\n";
  uint64_t n = 0;
  for (const Event& e : events) {
    if (e.x >= width || e.y >= height) continue;
    const bool accepted = sae.update(e);
    const frontend::CornerResult r = detector.detect(e, accepted);
    if (!r.corner) continue;
    out << fmt::format("{:.9f} {} {} {:.2f}\n", e.t_ns * 1e-9, e.x, e.y, r.score);
    ++n;
  }
  fmt::print("corners           {} written to {}\n", n, path);
}

}  // namespace

int main(int argc, char** argv) try {
  Config config;
  bool accel = false;
  std::string tracks_path;
  std::string ends_path;
  int worst = 0;
  std::string corners_path;
  sim::FeatureAccuracyOptions accuracy;
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--yaml" && i + 1 < argc) {
      applyConfigYaml(argv[++i], "--yaml", config);
    } else if (a == "--accel") {
      accel = true;
    } else if (a == "--synthetic") {
      dirs.push_back("@synthetic");
    } else if (a == "--sim" && i + 1 < argc) {
      dirs.push_back(std::string("@sim:") + argv[++i]);
    } else if (a == "--worst" && i + 1 < argc) {
      worst = std::stoi(argv[++i]);
    } else if (a == "--corners" && i + 1 < argc) {
      corners_path = argv[++i];
    } else if (a == "--time-offset-ms" && i + 1 < argc) {
      accuracy.time_offset_ns = std::llround(std::stod(argv[++i]) * 1e6);
    } else if (a == "--tracks" && i + 1 < argc) {
      tracks_path = argv[++i];
    } else if (a == "--ends" && i + 1 < argc) {
      ends_path = argv[++i];
    } else if (a == "-h" || a.rfind("--", 0) == 0) {  // --help, or a flag unknown or without its value
      const bool help = a == "--help" || a == "-h";
      fmt::print(help ? stdout : stderr,
                 "usage: frontend_eval [--yaml YAML] [--accel] [--tracks FILE] [--ends FILE] [--worst N] [--time-offset-ms MS] "
                 "[--corners FILE] "
                 "(DIR | --sim SCENE:MOTION:SECONDS[:SEED] | --synthetic)...\n");
      return help ? 0 : 2;
    } else {
      dirs.push_back(a);
    }
  }
  for (const std::string& dir : dirs) {
    if (dir == "@synthetic") {
      evaluateSynthetic(config);
      continue;
    }
    if (dir.rfind("@sim:", 0) == 0) {
      evaluateSimulated(config, dir.substr(5), worst, accuracy);
      continue;
    }
    const DatasetFiles files = resolveDataset(dir);  // events.aevt, events.txt, ...
    const std::vector<Event> events = readAllEvents(files.events);
    if (!files.calibration) throw InputError(dir, "no calib.txt or camchain.yaml (the camera model)");
    const CameraModel camera = readCalibration(*files.calibration);  // calib.txt: 240x180
    const bench::FrontendRun run = bench::runFrontend(config.frontend, events, camera);
    const frontend::MeasurementCollector& out = run.out;
    fmt::print("== {}\n{}", dir, run.stats.summary());
    if (!corners_path.empty()) writeCorners(config, events, camera.width(), camera.height(), corners_path);
    if (!tracks_path.empty()) {
      std::ofstream f(tracks_path);
      for (const auto& m : out.measurements)
        f << fmt::format("{} {:.9f} {:.3f} {:.3f}\n", m.feature_id, m.t_ns * 1e-9, m.x, m.y);
    }
    if (!ends_path.empty()) {
      std::ofstream f(ends_path);
      for (const frontend::FeatureEnd& e : out.ends)
        f << fmt::format("{} {:.9f} {} {}\n", e.feature_id, e.t_ns * 1e-9, frontend::dropReasonName(e.reason),
                         e.measurements);
    }
    if (sim::isSimulatedDataset(dir)) {
      printAccuracy(out.measurements, sim::loadSimulatedGroundTruth(dir), worst, accuracy);
      continue;
    }
    frontend::RotationFitOptions options;
    options.with_acceleration = accel;
    try {
      const auto r = frontend::fitCommonRotation(out.measurements, camera.fx(), camera.fy(), options);
      fmt::print("rotation fit      {} tracks ({} excluded), {} measurements, {} iterations\n", r.tracks_used,
                 r.tracks_excluded, r.measurements, r.iterations);
      fmt::print("residual px       median {:.3f}  p90 {:.3f}  rms {:.3f}  >3px {:.1f} %\n", r.median_px,
                 r.p90_px, r.rms_px, 100 * r.share_above_3px);
      fmt::print("lifetime s        median {:.4f}  mean {:.4f}  max {:.4f}\n", r.lifetime_median_s,
                 r.lifetime_mean_s, r.lifetime_max_s);
      fmt::print("omega fit         {:+.3f} {:+.3f} {:+.3f} rad/s (|w| {:.3f})\n", r.omega.x(), r.omega.y(),
                 r.omega.z(), r.omega.norm());
      if (accel)
        fmt::print("alpha fit         {:+.2f} {:+.2f} {:+.2f} rad/s^2\n", r.alpha.x(), r.alpha.y(),
                   r.alpha.z());
    } catch (const std::exception& e) {
      fmt::print("rotation fit      not possible: {}\n", e.what());
    }
    std::ifstream motion(dir + "/motion.txt");
    double wx, wy, wz;
    if (motion >> wx >> wy >> wz)
      fmt::print("motion.txt gyro   {:+.3f} {:+.3f} {:+.3f} rad/s (|w| {:.3f})\n", wx, wy, wz,
                 Eigen::Vector3d(wx, wy, wz).norm());
    if (std::filesystem::exists(dir + "/groundtruth.txt")) {
      const Eigen::Vector3d w =
          mocapAngularVelocity(dir + "/groundtruth.txt", events.front().t_ns, events.back().t_ns);
      fmt::print("mocap mean        {:+.3f} {:+.3f} {:+.3f} rad/s (|w| {:.3f}) over the slice\n", w.x(),
                 w.y(), w.z(), w.norm());
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::cerr << "frontend_eval: " << e.what() << "\n";
  return 1;
}
