#pragma once
// Configuration of the continuous-time backend (DESIGN.md §4 Backend; docs/backend.md).

#include <cstdint>
#include <string>
#include <vector>

namespace asynevo {

struct BackendConfig {
  // --- trajectory and prior ---
  double knot_dt_ms = 50.0;  ///< knot spacing in event time
  /// Power-spectral density of the WNOA prior, diagonal [tx ty tz rx ry rz]: (m/s²)²·s for
  /// translation, (rad/s²)²·s for rotation. Monocular: translation units follow the map scale.
  std::vector<double> q_c = {10.0, 10.0, 10.0, 0.3, 0.3, 0.3};

  // --- measurements ---
  double pixel_sigma = 1.0;     ///< measurement standard deviation in pixels
  double huber_px = 2.0;        ///< Huber loss threshold in pixels
  double outlier_px = 5.0;      ///< after a solve, measurements with larger reprojection error are removed
  /// After a solve, a landmark whose RMS reprojection error over its window measurements exceeds this
  /// is removed and its feature ignored from then on (a corner that is no fixed scene point, e.g. a
  /// T-junction at a depth discontinuity, or a drifting tracker). 0 disables.
  double track_outlier_rms_px = 3.0;
  /// Backend-guided track splitting: after a solve, when a landmark's newest measurements all miss it
  /// by more than this (at least track_split_min_measurements of them in a row, after an older part that
  /// fits), the feature's tracker has drifted onto another point: those measurements and the feature's
  /// later ones become a new trajectory, triangulated on its own. 0 disables.
  double track_split_px = 0.0;
  int track_split_min_measurements = 3;  ///< trailing measurements beyond track_split_px that split a track
  /// Landmark rejoin: a new trajectory whose every view lies within this of the projection of one
  /// window landmark no longer measured (and of no other) extends that landmark instead of being
  /// triangulated on its own (backend/landmark_rejoin.hpp). 0 disables.
  double landmark_rejoin_px = 0.0;
  /// Landmark rejoin: the longest time from the landmark's last measurement to the new trajectory's first.
  double landmark_rejoin_max_gap_ms = 50.0;

  // --- triangulation of new trajectories ---
  int min_track_measurements = 5;      ///< measurements needed before a trajectory is triangulated
  double min_parallax_deg = 1.0;       ///< minimum angle between the first and last rays
  double max_triangulation_px = 3.0;   ///< maximum reprojection error of a fresh triangulation
  /// Which reprojection error of a fresh triangulation max_triangulation_px bounds: "max", the largest
  /// over its views, or "rms", their RMS (as track_outlier_rms_px bounds a landmark's after a solve).
  std::string triangulation_error = "max";
  /// Which views of a trajectory a new landmark is triangulated from while a segment is open: "all" its
  /// measurements in the window, "solved" those at times the latest solve covered (the knots added since
  /// are predicted at constant velocity, and their poses can be off under acceleration), or
  /// "solved_then_all": solved, then all where those are too few or hold too little parallax
  /// (TriangulationViews in triangulation.hpp).
  std::string triangulation_views = "solved_then_all";
  /// Resolution rule for the window's pixel bounds (huber_px, outlier_px, track_outlier_rms_px,
  /// track_split_px, max_triangulation_px, loss_max_median_px): > 0, they are given for a camera of this
  /// focal length and a camera of a longer one scales them by its focal length / this value (they are
  /// angles there; never below the pixel value); 0, they are the sensor's own pixels. pixel_sigma (the
  /// weight) is not scaled.
  double pixel_bounds_focal_px = 0.0;
  double min_depth = 0.05;             ///< minimum depth in map units (cheirality)
  /// A landmark deeper than this factor times the median depth of the window's landmarks, or shallower
  /// than the median divided by it, is not created, and one that drifts there in a solve goes back to
  /// an untriangulated trajectory (low-parallax landmarks run away in slow phases). 0 disables.
  double landmark_depth_range = 6.0;

  // --- window ---
  int window_min_knots = 8;     ///< N_min: dynamic marginalization keeps at least this many knots
  int window_max_knots = 20;    ///< N_max: past this the oldest knot is marginalized anyway
  /// The window is extended by this many knots (knot_dt apart) before each update, so it is solved once
  /// per this many knots: fewer solves per second of events, the newest estimate that much later.
  int knots_per_update = 1;
  double marginalization_epsilon = 0.8;  ///< t_ε = (1 − ε) t_0 + ε t_N (paper Alg. 1: 0.8)
  double scale_anchor_sigma = 0.1;       ///< relative σ of the renewed scale anchor (0 disables renewal)
  /// The WNOA prior exerts no force along the monocular scale (WnoaPriorFactor's scale-free mode).
  bool scale_free_prior = true;
  /// Forced marginalization (N_max), the measurements of still-active landmarks in the marginalized
  /// segments: "fixed_poses" keeps them as projections from their (now fixed) interpolated poses,
  /// "prior" folds them into the Schur complement with the landmarks in the prior's blanket, "drop"
  /// discards them (the prior stays on knots only). docs/backend.md, "Forced marginalization".
  std::string forced_marginalization = "fixed_poses";

  /// Measurements of one track closer in time than this to the previous one kept are not used (0 = all):
  /// along a track the GP interpolation makes neighbouring measurements highly correlated.
  double track_measurement_dt_ms = 0.0;

  // --- solver ---
  int max_iterations = 5;
  /// The solve ends when a step changes the cost by at most this fraction of it (Ceres's function tolerance).
  double function_tolerance = 1e-6;
  /// The trust-region radius a window solve starts from (Ceres's initial_trust_region_radius, and its
  /// default): the Levenberg–Marquardt damping of the first step is 1 / this times the clamped diagonal.
  /// Wider radii converge faster from a warm start but end more segments on the evaluation matrix.
  double initial_trust_region_radius = 1e4;
  /// builtin solver: the Jacobians and normal equations are evaluated at every k-th step taken; the
  /// steps between reuse them with the gradient at the new values (1 = every step).
  int relinearize_every = 1;
  double max_solver_time_s = 0.2;
  /// Threads of a window solve: builtin, the factors' evaluation (the same result on any number); ceres and
  /// the full-history baselines, Ceres's threads (only 1 keeps offline runs bit-for-bit deterministic).
  int solver_threads = 1;
  /// The window's Levenberg–Marquardt solver: "builtin" (our own arrow-structured Schur solver,
  /// backend/window_solver.hpp; factors evaluated on solver_threads) or "ceres" (Ceres, DENSE_SCHUR,
  /// solver_threads).
  std::string window_solver = "builtin";
  /// The linear velocity written with each final knot: the central difference of the final positions over
  /// ±this many knots of its segment (backend/velocity_from_poses.hpp); 0 = the GP's knot velocity. The
  /// angular velocity is the GP's either way.
  int linear_velocity_span_knots = 3;

  // --- initialization ---
  /// Median parallax of the two views in pixels (ray angle × focal): first the raw image motion, then,
  /// after the five-point pose, the inliers' motion with the rotation removed.
  double init_min_parallax_px = 10.0;
  int init_min_features = 30;          ///< features seen at both initialization times
  int init_min_inliers = 25;           ///< five-point RANSAC inliers
  double init_ransac_px = 1.0;         ///< RANSAC threshold in pixels
  double init_window_ms = 500.0;       ///< span of the initialization window
  /// After this much event time of failed attempts (from the first measurement), the feature and
  /// inlier counts are multiplied by init_relaxed_fraction: a scene whose features live too briefly
  /// for 30 at both ends still starts, and one that has them keeps the stricter start.
  double init_relax_after_ms = 250.0;
  double init_relaxed_fraction = 0.5;
  /// Attempts still failing this long after the first measurement (event time), most of the once-relaxed
  /// ones for lack of features: the counts are multiplied by init_relaxed_fraction once more, for scenes
  /// with very few features (a scene that has them and waits for parallax keeps its counts). 0 = never.
  double init_relax_again_after_ms = 500.0;
  /// A restart after a segment ends, in a scene whose previous start was granted the second relaxation
  /// (short of features), begins with the counts relaxed twice instead of waiting init_relax_after_ms
  /// and init_relax_again_after_ms again: the scene is still short of features.
  bool init_restart_short_relaxed = true;
  /// Which start is tried: "two-view" (two times, five-point RANSAC), "multi-view" (one constant twist
  /// fitted to every track of the window) or "both" (two-view first; once the counts are relaxed,
  /// multi-view when it fails).
  std::string init_method = "both";
  /// When a start triangulates too few landmarks from its constant-twist knots, refit the knots'
  /// rotations to the tracks and triangulate again (backend/start_trajectory.hpp).
  bool init_refine_rotations = false;
  /// A motion is accepted as a start only when the attempt one knot interval earlier also found one
  /// whose translation direction (body frame) lies within this angle of it (0 = off): a start whose
  /// geometry is too weak to repeat is not built on (docs/method/initialization.md, "Agreement").
  double init_agreement_deg = 0.0;
  /// After the start's first solve, try the trajectories that did not become landmarks again, against
  /// the solved knots (the constant-twist knots they failed against are degrees off where the motion
  /// changes within the window), and solve again when some did.
  bool init_retriangulate = true;
  /// When a two-view start triangulates too few landmarks against its constant-twist knots, triangulate
  /// the trajectories seen at both of its times from those two views alone (the five-point pose) and
  /// let the first solve fit the knots to them.
  bool init_two_view_landmarks = true;
  /// A two-view start that passes only with the relaxed counts (fewer inliers than the unrelaxed
  /// init_min_inliers; a five-point pose from a dozen features can fit a depth-inverted map travelled in
  /// reverse, docs/method/initialization.md, "Weak two-view starts"): "keep" builds on it; "compare"
  /// tries the multi-view start of the same attempt too and takes the one with more inliers; "confirm"
  /// does the same but waits when the multi-view start fails.
  std::string init_weak_two_view = "keep";
  /// The depth-reversed alternative of a start's motion (docs/method/depth_reversal.md): "off" builds on
  /// the motion found; "best" also fits the alternative with the translation reversed and builds on it
  /// when its cost is below (1 − init_reversal_margin) times the motion's; "wait" does the same but
  /// rejects the span (a 'reversal' rejection) when the two costs lie within the margin of each other;
  /// "strict" never builds on the alternative and rejects the span unless the alternative is dearer than
  /// the motion by 1 / (1 − init_reversal_margin).
  std::string init_depth_reversal = "off";
  /// How much lower the alternative's cost must be to be built on (a fraction of the motion's cost); with
  /// "wait", costs this close are a tie that the span cannot decide.
  double init_reversal_margin = 0.2;

  // --- tracking loss (docs/method/tracking_loss.md): the segment ends, the estimator starts again ---
  double loss_max_event_gap_ms = 250.0;  ///< a gap in the events longer than this ends the segment (0 = off)
  int loss_min_landmarks = 5;            ///< a window with fewer landmarks is unsupported
  double loss_unsupported_ms = 0.0;      ///< unsupported for longer than this ends the segment (0 = off)
  /// Median reprojection error of the newest knot interval's measurements after a solve above this ends
  /// the segment (0 = off).
  double loss_max_median_px = 3.0;
  /// The median landmark depth leaving [d₀/r, d₀·r] (d₀: at the segment's start) ends it (0 = off).
  double loss_depth_ratio = 20.0;
  /// At a residual, depth or non-finite loss, write the window's knots as the last update that passed
  /// every test left them (the failed solve's knots are dropped either way).
  bool loss_write_accepted_window = true;
  /// The direction audit (docs/method/depth_reversal.md, "Auditing a young segment"): for
  /// direction_audit_ms after each start, every update compares the window's motion over the newest
  /// direction_audit_span_ms with its depth-reversed alternative. "off"; "log" records each comparison
  /// (init_reversals.txt, method audit); "restart" also ends the segment (a 'reversal' end) when the
  /// alternative's cost is below (1 − direction_audit_margin) times the motion's in
  /// direction_audit_votes consecutive audits.
  std::string direction_audit = "restart";
  double direction_audit_ms = 1000.0;
  double direction_audit_span_ms = 200.0;
  double direction_audit_margin = 0.33;
  int direction_audit_votes = 2;
  /// An audit needs this median parallax once the window's rotation is removed (a rotation leaves the
  /// direction of travel unobserved).
  double direction_audit_parallax_px = 3.0;
  /// The init_depth_reversal rule of the start that follows a 'reversal' end: "same" (init_depth_reversal
  /// as set), or off, best, wait, strict for that start alone.
  std::string direction_audit_restart_rule = "strict";

  template <class V>
  void visit(V& v) {
    v("knot_dt_ms", knot_dt_ms, "knot spacing in event time [ms] (20-50 ms; keep >= a few ms)");
    v("q_c", q_c, "WNOA power-spectral density diagonal [tx ty tz rx ry rz]");
    v("pixel_sigma", pixel_sigma, "measurement standard deviation [px]");
    v("huber_px", huber_px, "Huber loss threshold on projection residuals [px]");
    v("outlier_px", outlier_px, "after each solve, drop measurements with a larger reprojection error [px]");
    v("track_outlier_rms_px", track_outlier_rms_px,
      "after each solve, reject a whole trajectory whose RMS reprojection error is larger [px] (0 = off)");
    v("track_split_px", track_split_px,
      "after each solve, a landmark whose newest measurements all miss it by more than this is split: they "
      "start a new trajectory [px] (0 = off)");
    v("track_split_min_measurements", track_split_min_measurements,
      "track splitting: trailing measurements beyond track_split_px needed to split");
    v("landmark_rejoin_px", landmark_rejoin_px,
      "a new trajectory whose views all lie within this of the projection of one landmark no longer measured "
      "extends that landmark instead of being triangulated [px] (0 = off)");
    v("landmark_rejoin_max_gap_ms", landmark_rejoin_max_gap_ms,
      "landmark rejoin: longest time from the landmark's last measurement to the new trajectory's first "
      "[ms]");
    v("min_track_measurements", min_track_measurements, "measurements before a trajectory is triangulated");
    v("min_parallax_deg", min_parallax_deg, "minimum ray angle to triangulate a trajectory [deg]");
    v("max_triangulation_px", max_triangulation_px, "maximum reprojection error of a new landmark [px]");
    v("triangulation_error", triangulation_error,
      "which error of a new landmark max_triangulation_px bounds: max (over its views) or rms");
    v("triangulation_views", triangulation_views,
      "the views a new landmark is triangulated from in an open segment: all (in the window), solved (at "
      "times the latest solve covered, not the knots predicted since) or solved_then_all (solved, then all "
      "where those are too few or hold too little parallax)");
    v("pixel_bounds_focal_px", pixel_bounds_focal_px,
      "resolution rule: the window's pixel bounds are for a camera of this focal length; a longer one scales "
      "them by its focal length / this [px] (0 = the sensor's own pixels)");
    v("min_depth", min_depth, "minimum landmark depth (map units)");
    v("landmark_depth_range", landmark_depth_range,
      "landmarks beyond this factor of the median landmark depth, either way, are not kept (0 = off)");
    v("window_min_knots", window_min_knots, "N_min: the window keeps at least this many knots");
    v("window_max_knots", window_max_knots, "N_max: beyond this the oldest knot is marginalized anyway");
    v("knots_per_update", knots_per_update,
      "the window grows by this many knots before each update (triangulate, marginalize, solve): one "
      "solve per this many knots");
    v("marginalization_epsilon", marginalization_epsilon, "t_eps = (1 - eps) t_0 + eps t_N (paper: 0.8)");
    v("scale_anchor_sigma", scale_anchor_sigma,
      "relative sigma of the scale anchor renewed in the window once the initial one is marginalized (0 = off)");
    v("scale_free_prior", scale_free_prior,
      "the WNOA prior does not pull on the monocular scale (Jacobian projected off the scale direction)");
    v("forced_marginalization", forced_marginalization,
      "measurements of active landmarks at marginalized knots: fixed_poses, prior or drop");
    v("track_measurement_dt_ms", track_measurement_dt_ms,
      "a track's measurements closer than this to its previous one kept are not used [ms] (0 = all)");
    v("max_iterations", max_iterations, "Levenberg-Marquardt iterations per window solve");
    v("function_tolerance", function_tolerance,
      "a window solve ends when a step changes the cost by at most this fraction of it");
    v("initial_trust_region_radius", initial_trust_region_radius,
      "trust-region radius a window solve starts from: the first step's damping is 1/this times diag(H)");
    v("relinearize_every", relinearize_every,
      "builtin solver: Jacobians at every k-th step taken, the steps between reuse them (1 = every step)");
    v("max_solver_time_s", max_solver_time_s, "wall-time cap per window solve [s]");
    v("solver_threads", solver_threads,
      "threads of a window solve: builtin, factor evaluation (same result on any number); ceres, "
      "Ceres threads (1 = deterministic)");
    v("window_solver", window_solver, "the window's solver: builtin (own Schur solver) or ceres");
    v("linear_velocity_span_knots", linear_velocity_span_knots,
      "the linear velocity written with each final knot: central difference of the final positions over "
      "+-this many knots of its segment (0 = the GP's knot velocity; the angular velocity is the GP's)");
    v("init_min_parallax_px", init_min_parallax_px,
      "initialization: median parallax, raw and with the rotation removed [px]");
    v("init_min_features", init_min_features, "initialization: features seen at both times");
    v("init_min_inliers", init_min_inliers, "initialization: five-point RANSAC inliers");
    v("init_ransac_px", init_ransac_px, "initialization: RANSAC threshold [px]");
    v("init_window_ms", init_window_ms, "initialization: longest span searched for parallax [ms]");
    v("init_relax_after_ms", init_relax_after_ms,
      "initialization: event time of failed attempts after which the feature and inlier counts are relaxed [ms]");
    v("init_relaxed_fraction", init_relaxed_fraction,
      "initialization: factor on init_min_features and init_min_inliers once relaxed (1 = never relax)");
    v("init_relax_again_after_ms", init_relax_again_after_ms,
      "initialization: event time of failed attempts after which the counts are relaxed by "
      "init_relaxed_fraction once more, when most once-relaxed attempts lacked features [ms] (0 = never)");
    v("init_restart_short_relaxed", init_restart_short_relaxed,
      "initialization: a restart in a scene whose previous start was relaxed twice (short of features) "
      "begins relaxed twice");
    v("init_method", init_method, "initialization: two-view, multi-view or both (two-view first, multi-view once relaxed)");
    v("init_refine_rotations", init_refine_rotations,
      "initialization: refit the first knots' rotations to the tracks when too few landmarks triangulate");
    v("init_agreement_deg", init_agreement_deg,
      "initialization: a start needs the previous attempt's translation direction within this angle [deg] (0 = off)");
    v("init_two_view_landmarks", init_two_view_landmarks,
      "initialization: too few landmarks against the start's knots: triangulate from the start's two views alone");
    v("init_weak_two_view", init_weak_two_view,
      "initialization: a two-view start below the unrelaxed inlier count: keep, compare (with the multi-view start) or confirm (by it)");
    v("init_depth_reversal", init_depth_reversal,
      "initialization: the depth-reversed alternative of a start's motion: off, best (built on when it fits "
      "better by the margin), wait (the same, rejecting a near tie) or strict (a start only when it fits worse "
      "by the margin)");
    v("init_reversal_margin", init_reversal_margin,
      "initialization: the depth-reversed alternative is built on when its cost is lower by this fraction; with "
      "wait, costs this close are a tie");
    v("init_retriangulate", init_retriangulate,
      "initialization: after the start's solve, triangulate the remaining trajectories again and solve again");
    v("loss_max_event_gap_ms", loss_max_event_gap_ms,
      "tracking loss: a gap in the events longer than this ends the segment [ms] (0 = off)");
    v("loss_min_landmarks", loss_min_landmarks, "tracking loss: fewer landmarks in the window is unsupported");
    v("loss_unsupported_ms", loss_unsupported_ms,
      "tracking loss: unsupported for longer than this ends the segment [ms] (0 = off)");
    v("loss_max_median_px", loss_max_median_px,
      "tracking loss: a median reprojection error of the newest measurements above this after a solve ends the "
      "segment [px] (0 = off)");
    v("loss_depth_ratio", loss_depth_ratio,
      "tracking loss: the median landmark depth changing by more than this factor ends the segment (0 = off)");
    v("loss_write_accepted_window", loss_write_accepted_window,
      "tracking loss: at a residual, depth or non-finite loss, write the window's knots of the last update that "
      "passed every test");
    v("direction_audit", direction_audit,
      "tracking loss: after a start, compare the window's motion with its depth-reversed alternative: off, log, or "
      "restart (end the segment when the alternative fits better by the margin, votes times in a row)");
    v("direction_audit_ms", direction_audit_ms, "tracking loss: how long after a start the direction is audited [ms]");
    v("direction_audit_span_ms", direction_audit_span_ms,
      "tracking loss: the span of the window's motion each audit compares [ms]");
    v("direction_audit_margin", direction_audit_margin,
      "tracking loss: an audit votes against the segment when the alternative's cost is lower by this fraction");
    v("direction_audit_votes", direction_audit_votes,
      "tracking loss: consecutive votes against the segment that end it (direction_audit: restart)");
    v("direction_audit_parallax_px", direction_audit_parallax_px,
      "tracking loss: an audit needs this median parallax once the window's rotation is removed [px]");
    v("direction_audit_restart_rule", direction_audit_restart_rule,
      "tracking loss: the init_depth_reversal rule of the start after a reversal: same (as set), off, best, wait or "
      "strict");
  }
  void validate() const;
};

}  // namespace asynevo
