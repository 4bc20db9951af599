#pragma once
// The backend interface: both AsynEVO's sliding-window estimator and the incremental baseline
// implement it, so the pipeline and the CLI do not depend on which one runs (DESIGN.md §2, §4).
//
// Call order (one thread): any number of addMeasurement()/endFeature(), then advanceTo(t) whenever
// event time has reached t; decisions depend only on this call sequence (offline determinism).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "asynevo/backend/init_attempt.hpp"
#include "asynevo/backend/init_result.hpp"
#include "asynevo/backend/segment.hpp"
#include "asynevo/backend/trajectory.hpp"
#include "asynevo/frontend/track_measurement.hpp"

namespace asynevo::backend {

/// One backend update (a new knot and the work it triggered), for timing.csv.
struct UpdateRecord {
  int64_t event_t_ns = 0;    ///< event time that triggered the update
  int window_knots = 0;
  int landmarks = 0;
  int measurements = 0;      ///< projection factors in the solve
  /// Landmarks with a measurement in the newest knot interval: 0 while the window still holds landmarks
  /// means the newest knots rest on the motion prior alone (the window coasts).
  int recent_landmarks = 0;
  int iterations = 0;
  double triangulate_ms = 0;
  double marginalize_ms = 0;
  double solve_ms = 0;       ///< the window solve and the outlier removal after it
  // Parts of solve_ms (docs/backend.md, "Cost of one update"): building the factors and the Ceres problem,
  // Ceres's residual and Jacobian evaluations and linear solves, the rest of Ceres (preprocessing, the
  // trust-region bookkeeping), and the outlier removal.
  double solve_build_ms = 0;
  double solve_residuals_ms = 0;
  double solve_jacobians_ms = 0;
  double solve_linear_ms = 0;
  double solve_other_ms = 0;
  double outliers_ms = 0;
  double total_ms = 0;
  double final_cost = 0;
};

struct EstimatorStats {
  bool initialized = false;       ///< initialized at least once
  int64_t initialized_at_ns = 0;  ///< the first initialization
  uint64_t init_attempts = 0;
  std::string init_last_failure;  ///< why the last initialization attempt failed (with counts)
  /// Failed attempts by the furthest check they reached (indexed by InitRejection; see rejectionName).
  std::array<uint64_t, kInitRejections> init_rejections{};
  /// Every failed attempt, oldest first, up to kMaxInitAttemptsLogged (init_attempts.txt).
  std::vector<InitAttempt> init_attempt_log;
  uint64_t init_attempts_not_logged = 0;  ///< failed attempts past kMaxInitAttemptsLogged
  /// Every comparison of a start's motion with its depth-reversed alternative (init_depth_reversal),
  /// oldest first, up to kMaxInitAttemptsLogged (init_reversals.txt).
  std::vector<ReversalCheck> init_reversal_log;
  /// Attempts whose knots were refitted (init_refine_rotations) after too few landmarks triangulated.
  uint64_t init_rotation_refits = 0;
  /// Starts whose first solve let more trajectories become landmarks (init_retriangulate).
  uint64_t init_retriangulations = 0;
  /// Two-view starts that triangulated landmarks from their two views alone (init_two_view_landmarks).
  uint64_t init_two_view_landmark_starts = 0;
  /// Starts made from the multi-view fit instead of a weak two-view pose (init_weak_two_view).
  uint64_t init_weak_two_view_replaced = 0;
  /// Two-view starts built on the depth-reversed alternative of their five-point pose (init_depth_reversal).
  uint64_t init_depth_reversed = 0;
  /// Direction audits of young segments (direction_audit), and those that voted against the segment.
  uint64_t direction_audits = 0;
  uint64_t direction_audit_votes = 0;
  /// Times the counts were relaxed a second time (init_relax_again_after_ms; granted only where the
  /// once-relaxed attempts failed mostly for lack of features), over the first start and every restart.
  uint64_t init_relaxed_again = 0;
  /// Restarts that began with both relaxations (init_restart_short_relaxed).
  uint64_t init_restarts_relaxed = 0;
  /// The two views the estimator started from (valid once initialized).
  struct InitViews {
    std::string method;      ///< "two-view" or "multi-view"
    double span_ms = 0;      ///< t_b − t_a
    int features = 0;        ///< seen at both times
    int inliers = 0;         ///< five-point inliers in front of both cameras
    double parallax_px = 0;  ///< median inlier parallax with the rotation removed
    int landmarks = 0;       ///< triangulated right after
  } init_views;
  uint64_t measurements_received = 0;
  uint64_t measurements_before_window = 0;  ///< arrived for a time older than the window: dropped
  uint64_t measurements_out_of_order = 0;   ///< earlier than the same feature's previous one: dropped
  uint64_t measurements_subsampled = 0;     ///< within track_measurement_dt_ms of the track's previous one
  uint64_t knots = 0;
  uint64_t updates = 0;
  uint64_t landmarks_created = 0;
  std::array<uint64_t, 6> triangulation_failures{};  ///< by TriangulationFailure
  uint64_t marginalizations = 0;
  uint64_t knots_marginalized = 0;
  uint64_t landmarks_marginalized = 0;
  uint64_t forced_marginalizations = 0;          ///< N_max safeguard used
  uint64_t observations_dropped_forced = 0;      ///< dropped to keep the prior on knots only
  uint64_t observations_fixed_pose = 0;    ///< of active landmarks, kept from fixed poses (forced case)
  uint64_t observations_marginalized = 0;  ///< of active landmarks, folded into the prior (forced case)
  uint64_t landmarks_released = 0;  ///< rejected or lost landmarks marginalized out of the prior
  uint64_t observations_dropped_untriangulated = 0;  ///< of trajectories never triangulated, leaving the window
  uint64_t outliers_removed = 0;
  uint64_t landmarks_lost = 0;  ///< fewer than two observations left after outlier removal
  uint64_t tracks_rejected = 0;  ///< whole trajectories rejected by the RMS test (track_outlier_rms_px)
  uint64_t tracks_split = 0;  ///< trajectories whose newest measurements started a new one (track_split_px)
  /// new trajectories that extended a landmark no longer measured (landmark_rejoin_px)
  uint64_t landmarks_rejoined = 0;
  uint64_t rejoins_ambiguous = 0;   ///< rejoin tests where more than one landmark fitted (none taken)
  uint64_t measurements_of_superseded_features = 0;  ///< of features a rejoin took the landmark from, ignored
  uint64_t measurements_of_rejected_tracks = 0;  ///< later measurements of rejected trajectories, ignored
  uint64_t landmarks_depth_rejected = 0;         ///< triangulations outside landmark_depth_range, not created
  uint64_t landmarks_depth_reset = 0;  ///< left landmark_depth_range in a solve: untriangulated again
  uint64_t scale_anchors = 0;  ///< scale anchors renewed after the initial one left the window
  int max_window_knots = 0;
  int last_prior_rank = 0;
  /// Segments of the estimate, oldest first (the last one is open while tracking). Empty for
  /// estimators without tracking-loss detection.
  std::vector<Segment> segments;
  uint64_t knots_dropped_at_loss = 0;       ///< window knots not written when tracking was lost
  uint64_t measurements_before_reset = 0;   ///< older than the latest tracking loss: dropped
  uint64_t measurements_non_finite = 0;     ///< NaN or infinite coordinates: dropped
  /// Largest median reprojection error of a window after a solve that did not end its segment [px]
  /// (what loss_max_median_px is judged against).
  double max_median_residual_px = 0;
  /// Largest ratio max(d/d₀, d₀/d) of the median landmark depth to its value at the segment's start
  /// that did not end the segment (what loss_depth_ratio is judged against).
  double max_depth_ratio = 0;
};

/// "N ms apart: F features, I inliers, parallax P px, L landmarks": the two views initialization
/// started from, as the run summary and the backend replay print them.
std::string describeInitViews(const EstimatorStats::InitViews& views);

/// A triangulated landmark (world coordinates) for landmarks.ply.
struct LandmarkPoint {
  int64_t id = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  int observations = 0;
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  virtual const char* name() const = 0;
  virtual void addMeasurement(const TrackMeasurement& m) = 0;
  /// The frontend ended this feature: no more measurements will come for it.
  virtual void endFeature(int64_t feature_id) = 0;
  /// Event time has reached t_ns: add knots, triangulate, marginalize and solve as needed.
  virtual void advanceTo(int64_t t_ns) = 0;
  /// End of stream: final solve; every remaining knot becomes final.
  virtual void finish() = 0;

  /// Knots whose estimate will not change any more, oldest first, handed out once.
  virtual std::vector<Knot> takeFinalKnots() = 0;
  /// Update records since the last call.
  virtual std::vector<UpdateRecord> takeUpdateRecords() = 0;
  /// Landmarks marginalized since the last call plus, after finish(), all remaining ones.
  virtual std::vector<LandmarkPoint> takeFinalLandmarks() = 0;
  virtual const EstimatorStats& stats() const = 0;
};

}  // namespace asynevo::backend
