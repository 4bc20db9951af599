#pragma once
// AsynEVO's backend (DESIGN.md §4 Backend): a sliding window of GP knots every knot_dt of event time,
// every measurement a GP projection factor at its own time, WNOA priors between knots, Levenberg–
// Marquardt (Huber loss; our own Schur solver, window_solver.hpp, or Ceres DENSE_SCHUR), and dynamic
// marginalization (paper Alg. 1) with the N_max safeguard. docs/method/backend.md describes each step.

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/backend/init_result.hpp"
#include "asynevo/backend/factor_graph.hpp"
#include "asynevo/backend/feature_track.hpp"
#include "asynevo/backend/trajectory.hpp"
#include "asynevo/backend/triangulation.hpp"
#include "asynevo/backend/velocity_from_poses.hpp"
#include "asynevo/core/config/backend_config.hpp"

namespace ceres {
class Manifold;
}

namespace asynevo::backend {

class WindowSolverWorkspace;

struct EstimatorOptions {
  BackendConfig config;
  double focal_px = 200.0;  ///< mean focal length: converts pixel thresholds to normalized units
  bool real_time = false;   ///< enables the solver's wall-time cap (non-deterministic)
  bool marginalize = true;  ///< false: keep the whole history (the incremental baseline's mode)
  /// Sparse Schur complement (SuiteSparse) instead of the dense one: the full-history smoother's
  /// reduced camera matrix is banded and grows with the history, where dense elimination is cubic.
  bool sparse_linear_solver = false;
};

class SlidingWindowEstimator : public Estimator {
 public:
  /// Ids of the trajectories split off by track_split_px count up from here, far above any frontend
  /// feature id; the landmarks they become carry them.
  static constexpr int64_t kFirstSplitId = int64_t{1} << 40;

  explicit SlidingWindowEstimator(const EstimatorOptions& options);
  ~SlidingWindowEstimator() override;

  const char* name() const override { return "asynevo-sliding-window"; }
  void addMeasurement(const TrackMeasurement& m) override;
  void endFeature(int64_t feature_id) override;
  void advanceTo(int64_t t_ns) override;
  void finish() override;

  std::vector<Knot> takeFinalKnots() override;
  std::vector<UpdateRecord> takeUpdateRecords() override;
  std::vector<LandmarkPoint> takeFinalLandmarks() override;
  const EstimatorStats& stats() const override { return stats_; }

  const Trajectory& trajectory() const { return trajectory_; }
  /// Initialized and not lost since: a segment is open (docs/method/tracking_loss.md).
  bool tracking() const { return tracking_; }
  const TrackMap& tracks() const { return tracks_; }
  /// Feature ids whose trajectories the RMS test rejected (track_outlier_rms_px) and that have not ended.
  const std::set<int64_t>& rejectedFeatures() const { return rejected_features_; }
  /// Feature ids whose later measurements extend another trajectory, with its id: one split off by
  /// track_split_px, or a landmark the feature's trajectory rejoined (until the frontend ends the feature).
  const std::map<int64_t, int64_t>& splitFeatures() const { return split_aliases_; }

 protected:
  /// The factors of the current window (WNOA, projections of triangulated tracks up to the newest knot,
  /// the marginalization prior, the initial state prior) and the kind of every block they touch.
  struct ProjectionSource {
    FeatureTrack* track;
    std::size_t observation;  ///< index into track->observations
    std::size_t factor;       ///< index into the factor list
  };
  void buildFactors(std::vector<FactorEntry>& factors, std::map<double*, BlockKind>& kinds,
                    std::vector<ProjectionSource>* projection_sources);
  /// One Levenberg–Marquardt solve of the window; returns iterations and final cost.
  std::pair<int, double> solve(int max_iterations);
  /// solve() by the builtin solver (backend.window_solver: builtin) over factors valid at the start.
  std::pair<int, double> solveBuiltin(const std::vector<FactorEntry>& factors,
                                      const std::map<double*, BlockKind>& kinds, int max_iterations, double build_ms);
  /// Where the latest solve() spent its time (UpdateRecord's solve_* parts).
  struct SolveTimes {
    double build_ms = 0, residuals_ms = 0, jacobians_ms = 0, linear_ms = 0, other_ms = 0;
  };
  SolveTimes last_solve_times_;
  /// Triangulate, marginalize (when enabled), solve, remove outliers, record timing.
  void update(int64_t t_ns);
  /// Knots held constant in the solve (the frozen-history baseline overrides this).
  virtual bool isFrozen(const Knot& /*knot*/) const { return false; }
  const EstimatorOptions& options() const { return options_; }

 private:
  void tryInitialize(int64_t t_ns);
  /// The window's landmarks, their measurements in it and those measured in the newest knot interval.
  void countWindow(UpdateRecord& record) const;
  /// init_agreement_deg: the start's motion agrees with the one the previous attempt found. Keeps the
  /// motion for the next attempt; on disagreement records the failed attempt at t_ns.
  bool agreesWithPreviousAttempt(const InitResult& motion, int64_t t_ns);
  /// The configuration of an initialization attempt at t_ns: the counts relaxed once attempts have
  /// failed for init_relax_after_ms, and once more after init_relax_again_after_ms in a scene short of
  /// features (relaxed_again_).
  BackendConfig initConfig(int64_t t_ns) const;
  /// Grants the second relaxation of the counts: attempts have failed for init_relax_again_after_ms, and
  /// more of the once-relaxed attempts failed for lack of features than for anything else. A scene that
  /// has the features but waits for parallax (a rotation-dominated start) keeps the once-relaxed counts,
  /// whose parallax bound the multi-view start scales with.
  void updateRelaxedAgain(int64_t t_ns);
  /// Attempts have failed for init_relax_after_ms of event time since the first measurement.
  bool relaxed(int64_t t_ns) const;
  /// How many times the counts of an attempt at t_ns are relaxed: 0, 1 or 2.
  int relaxations(int64_t t_ns) const;
  /// Records a failed initialization attempt at t_ns: the last failure, the count by reason and the log.
  void rejectAttempt(int64_t t_ns, InitRejection rejection, std::string failure);
  /// The motion over the initialization window by config.init_method: two-view, multi-view, or both
  /// (the multi-view start once relaxed and the two-view start has failed).
  InitResult findInitialMotion(int64_t earliest_ns, int64_t t_b_ns, const BackendConfig& config,
                               bool relaxed_counts) const;
  void triangulateTracks();
  /// landmark_rejoin_px: the trajectory `from` extends the landmark `to` (its measurements and its live
  /// feature's later ones), `offset` (normalized) removed from them.
  void rejoinLandmark(int64_t from, int64_t to, const Eigen::Vector2d& offset);
  /// The frontend features whose measurements extend the trajectory `key` (by an alias, or by its own id).
  std::vector<int64_t> featuresFeeding(int64_t key) const;
  /// The triangulation checks of the configuration (parallax, reprojection error, depth).
  TriangulationOptions triangulationOptions() const;
  /// `track` becomes a landmark at `p_w` (counted in stats).
  void makeLandmark(FeatureTrack& track, const Eigen::Vector3d& p_w);
  /// Trajectories that are landmarks now.
  int landmarkCount() const;
  /// Tries every trajectory that is not a landmark again, against the knots as they are now (after the
  /// start's solve, init_retriangulate); returns how many became landmarks.
  int retriangulateUntriangulated();
  /// Each trajectory's normalized points at both times of a two-view start, by feature id.
  using TwoViewPoints = std::map<int64_t, std::pair<Eigen::Vector2d, Eigen::Vector2d>>;
  TwoViewPoints twoViewPoints(int64_t t_a_ns, int64_t t_b_ns) const;
  /// Landmarks from the two views of a two-view start alone (init_two_view_landmarks): the trajectories
  /// not yet landmarks, triangulated from their points and the poses at t_a and t_b; returns how many.
  int triangulateFromTwoViews(const TwoViewPoints& points, int64_t t_a_ns, int64_t t_b_ns);
  /// landmark_depth_range: depths in the newest knot's camera within a factor of the window
  /// landmarks' median depth. Admits everything when off or with fewer than 10 landmarks.
  struct DepthGate {
    lie::SE3 T_c_w;
    double min_depth = 0, max_depth = std::numeric_limits<double>::infinity();
    bool admits(const double* p_w) const;
  };
  DepthGate depthGate() const;
  /// Median depth of the window's landmarks in the camera `T_c_w`; 0 with fewer than `min_count`.
  double medianLandmarkDepth(const lie::SE3& T_c_w, std::size_t min_count) const;
  /// After an update: ends the segment when tracking is lost (docs/method/tracking_loss.md).
  void checkTracking(int64_t t_ns, int landmarks);
  /// direction_audit: compares the window's motion with its depth-reversed alternative (young segments
  /// only) and, with "restart", ends the segment after direction_audit_votes votes against it.
  void auditDirection(int64_t t_ns);
  /// Ends the open segment for `reason` at event time t_ns: the window's finite knots up to
  /// keep_until_ns are written, the rest dropped; the map is cleared and initialization starts again
  /// with measurements from reset_ns on.
  void loseTracking(SegmentEnd reason, int64_t t_ns, int64_t keep_until_ns, int64_t reset_ns);
  /// A loss whose solve failed (residual, depth, non-finite): the window's knots are dropped, or, with
  /// loss_write_accepted_window, those of the last accepted update not yet written are written instead.
  void loseTrackingAtFailedSolve(SegmentEnd reason, int64_t t_ns);
  /// Forgets the buffered trajectories and starts initialization afresh with measurements from
  /// reset_ns on (after a tracking loss, or a gap in the events before the first start).
  void restartInitialization(int64_t reset_ns);
  void marginalizeDynamic();
  void renewScaleAnchor();
  /// Marginalizes a landmark that leaves the estimation (rejected, lost) out of the prior, if in it.
  void releaseFromPrior(double* landmark);
  /// A landmark back to an untriangulated trajectory (out of the prior, retried on its next measurement).
  void untriangulate(FeatureTrack& track);
  /// After a solve: rejects whole trajectories failing the RMS test, then single measurements beyond
  /// outlier_px.
  void removeOutliers();
  /// track_split_px: moves a triangulated track's newest measurements to a new trajectory when they all
  /// miss its landmark (`norms`: its (observation index, whitened residual norm) in time order, the
  /// tail's removed on a split).
  void splitDriftedTail(FeatureTrack& track, std::vector<std::pair<std::size_t, double>>& norms);
  void finalizeKnot(const Knot& knot);
  void finalizeLandmark(const FeatureTrack& track);
  double normalizedThreshold(double px) const { return px / options_.focal_px; }

  EstimatorOptions options_;
  int64_t knot_dt_ns_;
  int64_t measurement_dt_ns_;  ///< config.track_measurement_dt_ms
  TriangulationViews triangulation_views_ = TriangulationViews::kAll;  ///< config.triangulation_views
  Eigen::Matrix<double, 6, 6> Q_c_;
  std::unique_ptr<ceres::Manifold> se3_manifold_;
  std::unique_ptr<WindowSolverWorkspace> solver_workspace_;  ///< the builtin solver's buffers, reused
  std::shared_ptr<ceres::LossFunction> huber_;

  Trajectory trajectory_;
  TrackMap tracks_;
  /// Frontend feature id → the trajectory its measurements now extend, for features split by
  /// track_split_px (forgotten when the frontend ends the feature).
  std::map<int64_t, int64_t> split_aliases_;
  int64_t next_split_id_ = kFirstSplitId;
  /// trajectories rejected by the RMS test whose feature has not ended: later measurements ignored
  std::set<int64_t> rejected_features_;
  /// Features whose landmark a new trajectory extended while they had not ended (landmark_rejoin_px):
  /// later measurements ignored, forgotten when the feature ends.
  std::set<int64_t> superseded_features_;
  /// Features that extend a rejoined landmark: the offset removed from their measurements (normalized).
  std::map<int64_t, Eigen::Vector2d> rejoin_offsets_;
  std::optional<FactorEntry> prior_;          ///< marginalization prior (knots, active landmarks)
  /// Gauge and scale anchors from initialization (a state prior on the first knot, a distance between
  /// two knots); each leaves for the marginalization prior with the first of its knots.
  struct Anchor {
    FactorEntry factor;
    std::vector<int64_t> knots;
  };
  std::vector<Anchor> anchors_;
  int64_t first_measurement_ns_ = -1;
  bool tracking_ = false;  ///< a segment is open (initialized and not lost since)
  int64_t reset_ns_ = std::numeric_limits<int64_t>::min();  ///< measurements before it are dropped
  int64_t last_supported_ns_ = 0;   ///< newest knot time with at least loss_min_landmarks landmarks
  int64_t solved_until_ns_ = -1;    ///< newest knot time of the latest solve (-1: none yet)
  double segment_depth_ = 0;        ///< median landmark depth at the segment's start (0: not yet known)
  int audit_votes_ = 0;             ///< consecutive direction audits of this segment against it
  double last_median_residual_px_ = 0;  ///< of the window's measurements after the latest solve
  std::optional<int64_t> last_init_attempt_ns_;
  /// Rejections of the once-relaxed attempts: for lack of features, and for any other reason.
  int relaxed_feature_rejections_ = 0;
  int relaxed_other_rejections_ = 0;
  bool relaxed_again_ = false;  ///< the second relaxation is granted (until the next restart)
  /// init_restart_short_relaxed: this restart begins with both relaxations (until the next restart).
  bool restart_relaxed_ = false;
  /// The motion the previous attempt found, when it found one (init_agreement_deg).
  std::optional<InitResult> previous_start_motion_;
  int64_t last_event_ns_ = 0;

  /// loss_write_accepted_window: the window's knots after the newest update that passed every test of
  /// checkTracking (empty before the segment's first such update).
  std::vector<Knot> accepted_window_;

  std::vector<Knot> final_knots_;
  VelocityFromPoses final_velocity_;  ///< each final knot's linear velocity, from the segment's positions
  std::vector<UpdateRecord> records_;
  std::vector<LandmarkPoint> final_landmarks_;
  EstimatorStats stats_;
};

}  // namespace asynevo::backend
