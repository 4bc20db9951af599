// Backend replay: runs an estimator on the feature tracks a run recorded, without the frontend,
// optionally with the measured positions replaced by their exact ground truth on a simulated sequence
// ("oracle" tracks: same features, same lifetimes, same times, positions from the scene). A diagnostic
// for docs/backend.md: it separates the error the frontend's tracks bring from the error of the backend.
//
//   bench_replay_tracks RUN_DIR DATASET_DIR OUT_TRAJ [--oracle NOISE_PX] [--drop-edges] [--incremental]
//                       [--seed N] [--dump-errors FILE] [--skip-ms MS] [--window-solver ceres|builtin]
//                       [--oracle-cut PX] [--oracle-scale F] [--oracle-min-age-ms MS]
//
// Writes OUT_TRAJ (TUM, as the run's stamped_traj_estimate.txt), OUT_TRAJ.velocities.txt (as its
// velocities.txt), OUT_TRAJ.segments.txt (as its segments.txt), OUT_TRAJ.updates.csv (the update
// records) and, with init_depth_reversal, OUT_TRAJ.init_reversals.txt (as its init_reversals.txt).
//
// --oracle: positions of features on a fixed scene point replaced by their projection plus Gaussian
// noise; features born on a depth discontinuity (no fixed 3D point) keep their measured positions.
// --drop-edges: features born on a depth discontinuity, or whose point leaves the view, are skipped.
// --oracle-cut PX: a feature on a fixed scene point loses its measurements from the first one more than
// PX from the truth on (what a test that ended every track at its first gross error would give).
// --oracle-scale F: the error of every measurement of a feature on a fixed scene point is multiplied by F
// (pixel = truth + F (measured - truth)): what uniformly better (F < 1) tracks of the same features give.
// --oracle-min-age-ms MS: --oracle-scale only for measurements at least MS after their track's first (what
// tracks whose error stopped growing with age would give).
// The oracle flags measure the error against the ray of the feature's first measurement, as
// frontend_eval does.
// --skip-ms: measurements in the first MS milliseconds after the first one are skipped, as if the
// recording had begun that much later (for the frontend's tracks as they were): the start comes from other
// windows of the same tracks. How much a sequence's result depends on when its start happens
// (docs/evaluation_matrix.md, "Start offsets").
// --window-solver: replaces the run's backend.window_solver, so both solvers replay the same run.
//
// RUN_DIR holds tracks.txt, backend_feed.txt and config.yaml (from 'asynevo run'), DATASET_DIR the
// sequence (calib.txt or a Kalibr camchain; for --oracle a folder written by 'asynevo simulate').
// Measurements are fed in file order (the order the backend took them), each time marker of
// backend_feed.txt after as many tracks.txt lines as the backend had taken before it, and normalized
// coordinates come from the frontend's undistortion table: without --oracle or --drop-edges the replay
// reproduces the run's trajectory byte for byte (tests/bench/replay_reproduces_run.sh). The feature ends are
// not replayed: the window estimator's output does not depend on them (it uses them only to forget
// what it kept about a feature that sends nothing more). A run folder without backend_feed.txt (older runs)
// gets a marker at every 1 ms up to each measurement's time, which misses the frontend's emission lag (a
// tracker's first state is recorded once its window has filled): on the demo its initialization then
// starts at 0.61 s instead of 1.16 s.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "asynevo/backend/incremental_estimator.hpp"
#include "asynevo/backend/sliding_window_estimator.hpp"
#include "asynevo/core/config/config.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/eval/statistics.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "asynevo/io/calibration_io.hpp"
#include "asynevo/io/dataset.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "asynevo/sim/feature_ground_truth.hpp"

using namespace asynevo;

namespace {

struct Args {
  std::string run, dataset, out;
  std::optional<double> oracle_noise_px;
  bool drop_edges = false;
  bool incremental = false;
  unsigned seed = 1;
  std::string dump_errors;  ///< --dump-errors FILE: measured vs exact pixel of every fixed-point measurement
  double skip_ms = 0;       ///< --skip-ms: measurements this long after the first are not fed
  std::string window_solver;  ///< --window-solver: overrides the run's backend.window_solver
  std::optional<double> oracle_cut_px;  ///< --oracle-cut
  std::optional<double> oracle_scale;   ///< --oracle-scale
  double oracle_min_age_ms = 0;         ///< --oracle-min-age-ms
};

Args parse(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: %s RUN_DIR DATASET_DIR OUT_TRAJ [--oracle NOISE_PX] [--drop-edges] [--incremental] "
                 "[--seed N] [--dump-errors FILE] [--skip-ms MS] [--window-solver ceres|builtin] "
                 "[--oracle-cut PX] [--oracle-scale F] [--oracle-min-age-ms MS]\n",
                 argv[0]);
    std::exit(2);
  }
  Args a{argv[1], argv[2], argv[3], std::nullopt, false, false, 1, {}, 0.0, {}, std::nullopt, std::nullopt, 0.0};
  auto positive = [&](int i) {
    const double v = std::stod(argv[i]);
    if (!(v >= 0)) {
      std::fprintf(stderr, "%s %s: not a number >= 0\n", argv[i - 1], argv[i]);
      std::exit(2);
    }
    return v;
  };
  for (int i = 4; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--oracle" && i + 1 < argc) {
      a.oracle_noise_px = std::stod(argv[++i]);
    } else if (flag == "--oracle-cut" && i + 1 < argc) {
      a.oracle_cut_px = positive(++i);
    } else if (flag == "--oracle-scale" && i + 1 < argc) {
      a.oracle_scale = positive(++i);
    } else if (flag == "--oracle-min-age-ms" && i + 1 < argc) {
      a.oracle_min_age_ms = positive(++i);
    } else if (flag == "--drop-edges") {
      a.drop_edges = true;
    } else if (flag == "--incremental") {
      a.incremental = true;
    } else if (flag == "--dump-errors" && i + 1 < argc) {
      a.dump_errors = argv[++i];
    } else if (flag == "--skip-ms" && i + 1 < argc) {
      a.skip_ms = std::stod(argv[++i]);
      if (!(a.skip_ms >= 0)) {
        std::fprintf(stderr, "--skip-ms %s: not a duration >= 0\n", argv[i]);
        std::exit(2);
      }
    } else if (flag == "--window-solver" && i + 1 < argc) {
      a.window_solver = argv[++i];
      if (a.window_solver != "ceres" && a.window_solver != "builtin") {
        std::fprintf(stderr, "--window-solver %s: not one of ceres, builtin\n", argv[i]);
        std::exit(2);
      }
    } else if (flag == "--seed" && i + 1 < argc) {
      a.seed = static_cast<unsigned>(std::stoul(argv[++i]));
    } else {
      std::fprintf(stderr, "unknown argument '%s'\n", flag.c_str());
      std::exit(2);
    }
  }
  return a;
}

struct FeedMarker {
  int64_t t_ns = 0;
  uint64_t measurements = 0;  ///< tracks.txt lines taken before the estimator advanced to t_ns
};

/// The run's backend_feed.txt ("t n" per time marker); empty when the run has none (older runs).
std::vector<FeedMarker> readFeed(const std::string& path) {
  std::vector<FeedMarker> feed;
  std::ifstream in(path);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string t_text;
    FeedMarker marker;
    fields >> t_text >> marker.measurements;
    const auto t_ns = parseSecondsToNs(t_text);
    if (!fields || !t_ns)
      throw std::runtime_error(fmt::format("{}:{}: bad line '{}'", path, line_number, line));
    marker.t_ns = *t_ns;
    feed.push_back(marker);
  }
  return feed;
}

}  // namespace

// Per-update time (median, p95, max) and where it goes: each stage's share of the summed update time
// (docs/backend.md, "Cost of one update"). Wall times of this process: compare two settings in one run.
static void printUpdateCost(const std::vector<backend::UpdateRecord>& records) {
  if (records.empty()) return;
  std::vector<double> total;
  double sum = 0;
  for (const auto& r : records) {
    total.push_back(r.total_ms);
    sum += r.total_ms;
  }
  fmt::print("update time: {} updates, median {:.2f} ms, p95 {:.2f} ms, max {:.2f} ms\n", records.size(),
             eval::percentile(total, 50), eval::percentile(total, 95), eval::percentile(total, 100));
  if (!(sum > 0)) return;
  const std::pair<const char*, double backend::UpdateRecord::*> stages[] = {
      {"triangulate", &backend::UpdateRecord::triangulate_ms},
      {"marginalize", &backend::UpdateRecord::marginalize_ms},
      {"solve: build", &backend::UpdateRecord::solve_build_ms},
      {"solve: residuals", &backend::UpdateRecord::solve_residuals_ms},
      {"solve: jacobians", &backend::UpdateRecord::solve_jacobians_ms},
      {"solve: linear", &backend::UpdateRecord::solve_linear_ms},
      {"solve: other", &backend::UpdateRecord::solve_other_ms},
      {"outliers", &backend::UpdateRecord::outliers_ms}};
  std::string shares;
  double covered = 0;
  for (const auto& [name, member] : stages) {
    double part = 0;
    for (const auto& r : records) part += r.*member;
    covered += part;
    shares += fmt::format("{}{} {:.0f} %", shares.empty() ? "" : ", ", name, 100 * part / sum);
  }
  fmt::print("update time shares: {}, rest {:.0f} %\n", shares, 100 * (sum - covered) / sum);
}

int main(int argc, char** argv) try {
  const Args args = parse(argc, argv);
  const Config config = loadConfig(args.run + "/config.yaml");
  // The calibration the run used: calib.txt or a Kalibr camchain, whichever the folder holds.
  const DatasetFiles files = resolveDataset(args.dataset);
  if (!files.calibration) throw std::runtime_error(args.dataset + ": no calib.txt or Kalibr camchain .yaml");
  const CameraModel camera = readCalibration(*files.calibration, config.sensor.width, config.sensor.height);
  // The frontend's undistortion (the same table, bilinear): normalized coordinates as the backend got them.
  const UndistortionTable<float> undistortion = camera.undistortionTable<float>();
  std::optional<sim::FeatureGroundTruth> truth;
  if (args.oracle_noise_px || args.drop_edges || !args.dump_errors.empty() || args.oracle_cut_px ||
      args.oracle_scale)
    truth.emplace(sim::loadSimulatedGroundTruth(args.dataset));

  backend::EstimatorOptions options;
  options.config = config.backend;
  if (!args.window_solver.empty()) options.config.window_solver = args.window_solver;
  // As 'asynevo run': pixel thresholds in the frontend's (binned) pixels.
  options.focal_px = 0.5 * (camera.fx() + camera.fy()) /
                     frontend::Frontend::binningFor(config.frontend, camera.width(), camera.height());
  std::unique_ptr<backend::Estimator> estimator;
  if (args.incremental) {
    estimator = std::make_unique<backend::IncrementalEstimator>(options, backend::IncrementalOptions{});
  } else {
    estimator = std::make_unique<backend::SlidingWindowEstimator>(options);
  }

  std::ofstream dump;
  if (!args.dump_errors.empty()) {
    dump.open(args.dump_errors);
    dump << "# id t x y x_true y_true\n";
  }
  std::ifstream in(args.run + "/tracks.txt");
  if (!in) throw std::runtime_error(args.run + "/tracks.txt: cannot open");
  std::mt19937 rng(args.seed);
  std::normal_distribution<double> noise(0.0, args.oracle_noise_px.value_or(0.0));
  std::map<int64_t, sim::FeatureGroundTruth::Anchor> anchors;
  std::map<int64_t, int64_t> first_seen_ns;  // --oracle-min-age-ms: each feature's first measurement
  std::set<int64_t> cut_features;  // --oracle-cut: features past their first gross error
  uint64_t cut = 0;
  std::string last_failure;
  auto advance = [&](int64_t marker) {
    estimator->advanceTo(marker);
    const auto& st = estimator->stats();
    // Waiting for a start: before the first one, and after a segment has ended (tracking loss).
    const bool waiting = st.segments.empty() || st.segments.back().ended_at_ns != 0;
    if (waiting && st.init_last_failure != last_failure) {
      last_failure = st.init_last_failure;
      fmt::print("{:.3f} s: {}\n", marker * 1e-9, last_failure);
    }
  };
  const std::vector<FeedMarker> feed = readFeed(args.run + "/backend_feed.txt");
  if (feed.empty()) fmt::print("no backend_feed.txt: markers approximated from the measurement times\n");
  std::size_t next_feed = 0;
  int64_t marker = 0;
  uint64_t lines = 0, fed = 0, skipped = 0;
  std::optional<int64_t> skip_until_ns;  // --skip-ms: from the first measurement's time
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    // The markers the pipeline's backend reached before it took this line.
    for (; next_feed < feed.size() && feed[next_feed].measurements <= lines; ++next_feed)
      advance(feed[next_feed].t_ns);
    ++lines;
    std::istringstream fields(line);
    int64_t id = 0;
    std::string t_text;
    float x = 0, y = 0;  // tracks.txt holds the frontend's floats exactly (shortest round-trip text)
    fields >> id >> t_text >> x >> y;
    if (!fields) throw std::runtime_error(fmt::format("{}/tracks.txt: bad line '{}'", args.run, line));
    TrackMeasurement m;
    m.feature_id = id;
    const auto t_ns = parseSecondsToNs(t_text);
    if (!t_ns) throw std::runtime_error(fmt::format("{}/tracks.txt: bad time '{}'", args.run, t_text));
    m.t_ns = *t_ns;
    // --skip-ms counts from the first line's time. Lines are in the frontend's output order, not
    // strictly in time (a measurement can be a little older than the line before it), so without
    // --skip-ms nothing is compared: every measurement is fed, as the run fed it.
    if (!skip_until_ns) skip_until_ns = m.t_ns + std::llround(args.skip_ms * 1e6);
    if (args.skip_ms > 0 && m.t_ns < *skip_until_ns) {
      ++skipped;
      continue;
    }
    Eigen::Vector2d pixel(x, y);
    if (truth) {
      auto anchor = anchors.find(id);
      if (anchor == anchors.end()) anchor = anchors.emplace(id, truth->anchor(m.t_ns, pixel)).first;
      const auto projection = anchor->second.valid ? truth->project(anchor->second.p_w, m.t_ns)
                                                   : sim::FeatureGroundTruth::Projection{};
      const bool fixed_point = projection.valid && !anchor->second.depth_edge;
      if (!fixed_point && args.drop_edges) {
        ++skipped;
        continue;
      }
      if (fixed_point && dump.is_open())
        dump << fmt::format("{} {:.6f} {:.3f} {:.3f} {:.3f} {:.3f}\n", id, m.t_ns * 1e-9, x, y,
                            projection.pixel.x(), projection.pixel.y());
      if (fixed_point && args.oracle_noise_px)
        pixel = projection.pixel + Eigen::Vector2d(noise(rng), noise(rng));
      if (fixed_point && args.oracle_cut_px &&
          (cut_features.count(id) > 0 || (pixel - projection.pixel).norm() > *args.oracle_cut_px)) {
        cut_features.insert(id);
        ++cut;
        continue;
      }
      const int64_t first_ns = first_seen_ns.emplace(id, m.t_ns).first->second;
      if (fixed_point && args.oracle_scale && (m.t_ns - first_ns) * 1e-6 >= args.oracle_min_age_ms)
        pixel = projection.pixel + *args.oracle_scale * (pixel - projection.pixel);
    }
    m.x = static_cast<float>(pixel.x());
    m.y = static_cast<float>(pixel.y());
    if (!undistortion.interpolate(m.x, m.y, m.xn, m.yn)) {
      ++skipped;
      continue;
    }
    if (feed.empty()) {
      const int64_t ms = m.t_ns / 1'000'000 * 1'000'000;
      if (marker == 0) marker = ms;  // the first marker comes one period after the first event
      while (ms > marker) advance(marker += 1'000'000);
    }
    estimator->addMeasurement(m);
    ++fed;
  }
  for (; next_feed < feed.size(); ++next_feed) advance(feed[next_feed].t_ns);
  estimator->finish();
  StampedTrajectory trajectory;
  std::vector<StampedTwist> twists;
  for (const backend::Knot& k : estimator->takeFinalKnots()) {
    const auto& p = k.pose;  // [t_x t_y t_z q_x q_y q_z q_w], written as the run folder writes it
    trajectory.push_back(
        {k.t_ns, Eigen::Vector3d(p[0], p[1], p[2]), Eigen::Quaterniond(p[6], p[3], p[4], p[5])});
    const auto& w = k.velocity;  // [v ω], body frame
    twists.push_back({k.t_ns, Eigen::Vector3d(w[0], w[1], w[2]), Eigen::Vector3d(w[3], w[4], w[5])});
  }
  std::sort(trajectory.begin(), trajectory.end(),
            [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  std::sort(twists.begin(), twists.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  writeTumTrajectory(args.out, trajectory);
  writeVelocities(args.out + ".velocities.txt", twists);  // for 'asynevo eval --velocities'
  // Comparisons with a depth-reversed alternative (docs/method/depth_reversal.md) as the run's init_reversals.txt.
  if (!estimator->stats().init_reversal_log.empty())
    std::ofstream(args.out + ".init_reversals.txt") << backend::initReversalsFileText(estimator->stats().init_reversal_log);
  // Segments (docs/method/tracking_loss.md) as the run's segments.txt, for 'asynevo eval --segments'.
  const std::vector<backend::Segment>& segments = estimator->stats().segments;
  if (!segments.empty()) {
    std::ofstream(args.out + ".segments.txt") << backend::segmentsFileText(segments);
    for (const backend::Segment& g : segments)
      fmt::print("segment {:.3f}-{:.3f} s, {} knots, ended by {}\n", g.t0_ns * 1e-9, g.t1_ns * 1e-9, g.knots,
                 backend::segmentEndName(g.end));
  }
  const std::vector<backend::UpdateRecord> records = estimator->takeUpdateRecords();
  {
    // The update records next to the trajectory (OUT_TRAJ.updates.csv) for plots of the window.
    std::ofstream updates(args.out + ".updates.csv");
    updates << "t,knots,landmarks,recent_landmarks,measurements,iterations,solve_ms,total_ms,final_cost\n";
    for (const auto& r : records)
      updates << fmt::format("{:.4f},{},{},{},{},{},{:.2f},{:.2f},{:.4g}\n", r.event_t_ns * 1e-9, r.window_knots,
                             r.landmarks, r.recent_landmarks, r.measurements, r.iterations, r.solve_ms, r.total_ms,
                             r.final_cost);
  }
  printUpdateCost(records);
  // Updates whose window held landmarks but none measured in the newest knot interval (the window coasted
  // on the motion prior), and the longest such stretch.
  int coasting = 0, run = 0, longest = 0;
  for (const auto& r : records) {
    run = r.landmarks > 0 && r.recent_landmarks == 0 ? run + 1 : 0;
    coasting += run > 0;
    longest = std::max(longest, run);
  }
  fmt::print("coasting updates: {} of {}, longest {} in a row\n", coasting, records.size(), longest);
  const auto stats = estimator->stats();
  fmt::print(
      "{}: fed {} measurements ({} skipped), {} knots, initialized {} at {:.3f} s after {} attempt(s)\n",
      estimator->name(), fed, skipped, trajectory.size(), stats.initialized, stats.initialized_at_ns * 1e-9,
      stats.init_attempts);
  if (stats.initialized) fmt::print("initial views {}\n", backend::describeInitViews(stats.init_views));
  if (args.oracle_cut_px)
    fmt::print("oracle cut: {} measurements of {} features dropped at their first error above {} px\n", cut,
               cut_features.size(), *args.oracle_cut_px);
  fmt::print(
      "landmarks {} (marginalized {}), tracks rejected {}, split {}, outliers {}, observations marginalized {}, "
      "dropped {} (forced) {} (untriangulated), scale anchors {}, depth gate {} rejected {} reset\n",
      stats.landmarks_created, stats.landmarks_marginalized, stats.tracks_rejected, stats.tracks_split, stats.outliers_removed,
      stats.observations_marginalized, stats.observations_dropped_forced,
      stats.observations_dropped_untriangulated, stats.scale_anchors, stats.landmarks_depth_rejected,
      stats.landmarks_depth_reset);
  if (stats.landmarks_rejoined || stats.rejoins_ambiguous)
    fmt::print("landmark rejoins {} ({} ambiguous tests, {} measurements of superseded features ignored)\n",
               stats.landmarks_rejoined, stats.rejoins_ambiguous, stats.measurements_of_superseded_features);
  const auto& tf = stats.triangulation_failures;  // by backend::TriangulationFailure
  fmt::print("triangulation failures: too few views {}, low parallax {}, degenerate {}, behind camera {}, high "
             "error {}\n",
             tf[1], tf[2], tf[3], tf[4], tf[5]);
  fmt::print("tracking loss: largest window median residual {:.2f} px, largest depth ratio {:.2f}\n",
             stats.max_median_residual_px, stats.max_depth_ratio);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "error: %s\n", e.what());
  return 1;
}
