#pragma once
// Running the frontend over a whole in-memory stream, and the exact tracking error on the synthetic
// stream (synthetic_stream.hpp): shared by frontend_eval and the accuracy tests, so they measure the
// same thing.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "asynevo/core/camera/undistortion_table.hpp"
#include "asynevo/core/config/frontend_config.hpp"
#include "asynevo/core/event.hpp"
#include "asynevo/frontend/frontend.hpp"
#include "synthetic_stream.hpp"

namespace asynevo::bench {

struct FrontendRun {
  frontend::MeasurementCollector out;  ///< every measurement and feature end, finish() included
  frontend::FrontendStats stats;
};

/// Feeds every event to `fe`, then finishes it.
inline FrontendRun feedAll(frontend::Frontend& fe, const std::vector<Event>& events) {
  FrontendRun run;
  for (const Event& e : events) fe.process(e, run.out);
  fe.finish(run.out);
  run.stats = fe.stats();
  return run;
}

/// Feeds every event to a fresh frontend, then finishes it.
inline FrontendRun runFrontend(const FrontendConfig& config, const std::vector<Event>& events, int width,
                               int height, UndistortionTable<float> undistortion = {}) {
  frontend::Frontend fe(config, width, height, std::move(undistortion));
  return feedAll(fe, events);
}

/// Feeds every event to a fresh frontend for `camera`'s sensor (rectified tracking as configured).
inline FrontendRun runFrontend(const FrontendConfig& config, const std::vector<Event>& events,
                               const CameraModel& camera) {
  frontend::Frontend fe(config, camera);
  return feedAll(fe, events);
}

/// Exact tracking error on syntheticStream(..., speed_px_s, ...): per track, at each measurement,
/// |(p(t) - p(t0)) + (offset(t) - offset(t0))| with t0 the track's first measurement (0 there).
struct SyntheticAccuracy {
  std::vector<double> errors_px;   ///< sorted, every measurement of the tracks used
  std::vector<double> lifetimes_s; ///< sorted, tracks used
  int tracks_used = 0;             ///< tracks with >= min_measurements (default 2: one carries no error)
  int bad_tracks = 0;              ///< error > bad_px reached, and the track lived > max_bad_survival_ns after
  /// Quantile f in [0, 1] of a sorted vector (0 for an empty one).
  static double quantile(const std::vector<double>& sorted, double f) {
    return sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(f * double(sorted.size() - 1))];
  }
  double shareAbove(double px) const {
    const auto above = errors_px.end() - std::upper_bound(errors_px.begin(), errors_px.end(), px);
    return errors_px.empty() ? 0.0 : double(above) / double(errors_px.size());
  }
};

inline SyntheticAccuracy evaluateSyntheticTracks(const std::vector<TrackMeasurement>& measurements,
                                                 double speed_px_s, std::size_t min_measurements = 2,
                                                 double bad_px = 5.0, int64_t max_bad_survival_ns = 20'000'000) {
  std::map<int64_t, std::vector<TrackMeasurement>> tracks;
  for (const auto& m : measurements) tracks[m.feature_id].push_back(m);
  SyntheticAccuracy r;
  for (const auto& [id, ms] : tracks) {
    if (ms.size() < min_measurements) continue;
    ++r.tracks_used;
    double ox0, oy0;
    syntheticOffset(speed_px_s, double(ms.front().t_ns) * 1e-9, ox0, oy0);
    int64_t first_bad = -1;
    for (const auto& m : ms) {
      double ox, oy;
      syntheticOffset(speed_px_s, double(m.t_ns) * 1e-9, ox, oy);
      const double e = std::hypot(m.x - ms.front().x + (ox - ox0), m.y - ms.front().y + (oy - oy0));
      r.errors_px.push_back(e);
      if (e > bad_px && first_bad < 0) first_bad = m.t_ns;
    }
    if (first_bad >= 0 && ms.back().t_ns - first_bad > max_bad_survival_ns) ++r.bad_tracks;
    r.lifetimes_s.push_back(double(ms.back().t_ns - ms.front().t_ns) * 1e-9);
  }
  std::sort(r.errors_px.begin(), r.errors_px.end());
  std::sort(r.lifetimes_s.begin(), r.lifetimes_s.end());
  return r;
}

}  // namespace asynevo::bench
