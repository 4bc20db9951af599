#pragma once
// Configuration of the event-driven frontend (DESIGN.md §4 Frontend, docs/frontend.md): refractory
// filter and SAE, corner detector (FA-Harris or Arc*), HASTE tracker, feature management.
// Defaults marked "(ref)" are the values of the reference implementations (Arc*: Alzugaray & Chli,
// RA-L 2018; FA-Harris: Li et al., IROS 2019; HASTE: Alzugaray & Chli, BMVC 2020), see
// shared/reference/frontend.md §5.2 and §6.6.

#include <cmath>
#include <cstdint>
#include <string>

namespace asynevo {

struct FrontendConfig {
  // --- sensor noise (docs/frontend.md, "Sensor noise") ---------------------------------------
  bool noise_filter = false;       ///< background-activity filter (Delbruck 2008) in front of everything
  double noise_filter_ms = 5.0;    ///< ...an event needs a neighbour's event within this long before it
  bool hot_pixel_filter = false;   ///< mask pixels that fire far above their neighbours
  double hot_pixel_window_ms = 1000.0;  ///< ...counted over windows of this much event time
  double hot_pixel_factor = 10.0;       ///< ...hot: count > factor x (mean count of the 8 neighbours + 1)
  double hot_pixel_min_rate_hz = 20.0;  ///< ...and at least this rate
  /// Peak-rate budget (frontend/event_rate_budget.hpp): events per second of event time processed in
  /// full, in millions; above it detection is skipped, above twice it events are shed. 0 = off.
  double max_event_rate_mev_s = 0.0;

  /// Events are binned b x b (pixel (x, y) -> (x / b, y / b)) before anything else, so the frontend works
  /// on a smaller image: 1, 2, 4 or 8; 0 = auto, the smallest power of two that brings the sensor's
  /// longer side to at most 400 px (DAVIS240C/346: 1, 640x480: 2, 1280x720: 4). Pixel-valued settings
  /// (here and the backend's) are then in binned pixels; measurements are reported in sensor pixels.
  int binning = 1;

  // --- refractory filter and SAE -------------------------------------------------------------
  double refractory_period_ms = 50.0;  ///< (ref) same-polarity refractory filter dt_f

  // --- corner detector --------------------------------------------------------------------------
  std::string detector = "fa_harris";  ///< "fa_harris" or "arc_star"
  double harris_threshold = 8.0;       ///< (ref) FA-Harris score threshold
  /// Adaptive detection: while fewer than 3/4 of max_features are active, the FA-Harris threshold falls
  /// by 5 % per 10 ms of event time, down to this fraction of harris_threshold; from 9/10 active it
  /// rises back at the same rate. 1 = a fixed threshold.
  double harris_threshold_floor = 0.25;
  double harris_k = 0.04;              ///< (ref) Harris k
  int harris_latest = 25;              ///< (ref) newest SAE pixels in the 9x9 window forming the patch

  // --- tracker ----------------------------------------------------------------------------------
  std::string tracker = "haste_correlation_star";  ///< or "haste_difference_star" (docs/frontend.md: why C*)
  double haste_hysteresis = 0.05;                  ///< (ref) hysteresis factor of the state switch
  double haste_template_update = 0.1;              ///< (ref) template update factor alpha (0 = frozen)

  // --- feature management -----------------------------------------------------------------------
  int max_features = 60;             ///< active features at most (seeding stops at this number)
  double min_distance_px = 15.0;     ///< patch search: no new feature within this of an active one
  /// Resolution rule: min_distance_px and neighbour_radius_px are given for a 240x180 image (diagonal
  /// 300 px) and scale with the frontend image's diagonal (distanceScale), so a feature budget spreads
  /// over a larger sensor as it does over a DAVIS240C. Off: both are used as given.
  bool scale_distances = false;
  double border_margin_px = 16.0;    ///< features are removed (and never seeded) this close to the border
  double collision_radius_px = 1.5;  ///< two features closer than this: the younger one is dropped
  double min_dt_ms = 5.0;            ///< minimum event time between two recorded measurements of a feature
  double max_idle_ms = 100.0;        ///< a feature without state change for this long is dropped...
  /// ...if meanwhile the features moved this many pixels on average (state changes per active feature;
  /// 0: time alone decides). A camera at rest, or reversing, moves no tracker: its features stay.
  double idle_min_scene_motion_px = 1.0;
  double init_timeout_ms = 100.0;    ///< a tracker not initialized after this long is dropped...
  /// ...once the tracking features have also moved this many pixels on average since it was created
  /// (state changes per initialized feature; 0: time alone decides). A slow scene gives a weak corner
  /// longer to gather its first window; a fast one drops it as early as before.
  double init_timeout_scene_px = 12.0;
  /// With init_timeout_scene_px: a tracker not initialized after this long is dropped however little
  /// the scene moved (a stream whose trackers all wait moves none of them).
  double init_timeout_max_ms = 500.0;
  double housekeeping_ms = 1.0;      ///< period (event time) of the idle/time-out/quality checks
  double min_anisotropy = 0.06;      ///< quality: min eigenvalue ratio of the window events' spread
  double max_drift_px = 4.0;         ///< drift test: max offset of the first-template match (0 = off)
  double drift_check_ms = 10.0;      ///< event-time period of a feature's drift test
  double max_rotation_deg = 20.0;  ///< rotation test: max departure from the features' common roll (0 = off)
  /// Neighbour-motion test: a feature whose displacement over the last neighbour_window_ms differs by more
  /// than this from the median displacement of its neighbour_count nearest features is dropped (0 = off).
  double max_neighbour_disagreement_px = 4.0;
  /// ... plus this fraction of the length of the neighbours' median displacement (0 = a fixed bound).
  double neighbour_disagreement_fraction = 0.0;
  /// "translation": the reference is the neighbours' median displacement; "similarity": each neighbour's
  /// displacement is first carried to the feature's position through the rotation and scale change the
  /// neighbours share (a roll or a zoom moves points apart in proportion to their distance); "either":
  /// dropped only when both references disagree.
  std::string neighbour_motion_model = "translation";
  /// With "either": the similarity reference is consulted only when it moves the feature by at least this
  /// much relative to its neighbours ((z - 1)(p_f - their mean position)); 0 = always.
  double neighbour_similarity_min_px = 1.0;
  /// With "either": a feature the similarity keeps is still dropped when a neighbour's carried displacement
  /// lies farther than this from their median (the neighbours do not follow it); 0 = off.
  double neighbour_similarity_agreement_px = 0.0;
  double neighbour_check_ms = 5.0;  ///< event-time period of the neighbour-motion test (all features at once)
  double neighbour_window_ms = 60.0;  ///< time span of the compared displacements (<= 100)
  int neighbour_count = 6;            ///< nearest features whose median displacement is the reference
  double neighbour_radius_px = 60.0;  ///< only features within this distance count as neighbours
  double max_time_reversal_us = 0.0;  ///< events earlier than their predecessor by more are dropped
  /// Measurements at the vertex of a parabola through the scores of the ±1 px hypotheses (x and y
  /// apart) instead of the 1-px state grid.
  bool subpixel_measurements = true;
  /// The trackers work on the rectified (undistorted pinhole) image instead of the raw pixels
  /// (frontend/tracking_frame.hpp); needs the camera model (Frontend(config, camera)).
  bool rectified_tracking = false;
  /// How a measurement's sub-pixel offset is found (docs/method/frontend.md, "Sub-pixel measurements"):
  /// "parabola" (the vertex through the +-1 px hypothesis scores) or "template_fit" (a continuous fit of
  /// the window to the blurred template).
  std::string subpixel_method = "parabola";

  template <class V>
  void visit(V& v) {
    v("noise_filter", noise_filter,
      "background-activity filter (Delbruck 2008): an event reaches the SAE, the detector and the trackers "
      "only when one of its 8 neighbours fired within noise_filter_ms before it");
    v("noise_filter_ms", noise_filter_ms, "background-activity filter: support window (ms, > 0)");
    v("hot_pixel_filter", hot_pixel_filter,
      "hot-pixel filter: a pixel whose event count in a window exceeds hot_pixel_factor x (the mean count of "
      "its 8 neighbours + 1) and hot_pixel_min_rate_hz is masked for the rest of the stream");
    v("hot_pixel_window_ms", hot_pixel_window_ms, "hot-pixel filter: counting window of event time (ms, > 0)");
    v("hot_pixel_factor", hot_pixel_factor, "hot-pixel filter: how far above its neighbours a hot pixel fires");
    v("hot_pixel_min_rate_hz", hot_pixel_min_rate_hz, "hot-pixel filter: the least rate of a hot pixel (Hz)");
    v("max_event_rate_mev_s", max_event_rate_mev_s,
      "peak-rate budget [M events/s of event time]: above it, per 1 ms window, no corner detection; above "
      "twice it, events are shed evenly before the SAE and the trackers (counted); 0 = off");
    v("binning", binning,
      "bin events b x b before the frontend (1, 2, 4, 8; 0 = auto: the sensor's longer side to <= 400 px); "
      "pixel settings are then in binned pixels");
    v("refractory_period_ms", refractory_period_ms,
      "refractory filter: an event is ignored by the detector when its pixel fired with the same "
      "polarity less than this ago and did not flip polarity since (Arc*/FA-Harris: 50 ms)");
    v("detector", detector, "corner detector: fa_harris (Arc* candidate + Harris refinement) or arc_star");
    v("harris_threshold", harris_threshold,
      "FA-Harris: a candidate is a corner when the Harris score of its binary 9x9 patch exceeds this");
    v("harris_threshold_floor", harris_threshold_floor,
      "FA-Harris: with fewer than 3/4 of max_features active the threshold falls (5 % per 10 ms) down to this "
      "fraction of harris_threshold, and rises back from 9/10 active (1 = fixed)");
    v("harris_k", harris_k, "FA-Harris: k of the Harris score A*C - B^2 - k*(A+C)^2");
    v("harris_latest", harris_latest,
      "FA-Harris: the binary patch holds this many newest pixels of the 9x9 window (reference: 25)");
    v("tracker", tracker,
      "feature tracker: haste_correlation_star (default: more accurate and faster on our measurements) or "
      "haste_difference_star (the reference default)");
    v("haste_hysteresis", haste_hysteresis,
      "HASTE: switch to the best hypothesis when (best - null) / (best - worst) exceeds this");
    v("haste_template_update", haste_template_update,
      "HASTE: weight (times 1/N) of the middle window event added to the template per event; 0 freezes it");
    v("max_features", max_features, "most features tracked at once; seeding stops at this number");
    v("min_distance_px", min_distance_px,
      "a corner seeds a feature only when no active feature is within this distance (patch search)");
    v("scale_distances", scale_distances,
      "resolution rule: min_distance_px and neighbour_radius_px are for a 240x180 image and scale with the "
      "frontend image's diagonal (x diagonal / 300 px)");
    v("border_margin_px", border_margin_px,
      "features closer than this to the image border are removed and never seeded there");
    v("collision_radius_px", collision_radius_px,
      "two features closer than this are duplicates: the younger one is dropped");
    v("min_dt_ms", min_dt_ms, "minimum event time between two recorded measurements of one feature");
    v("max_idle_ms", max_idle_ms, "a feature whose state has not changed for this long is dropped...");
    v("idle_min_scene_motion_px", idle_min_scene_motion_px,
      "...if meanwhile the features moved this far on average [px] (0 = time alone; a camera at rest keeps its features)");
    v("init_timeout_ms", init_timeout_ms,
      "a tracker that has not gathered its first event window after this long is dropped...");
    v("init_timeout_scene_px", init_timeout_scene_px,
      "...once the tracking features have also moved this far on average since it was created [px] (0 = time "
      "alone; a slow scene gives a weak corner longer to fill its first window)");
    v("init_timeout_max_ms", init_timeout_max_ms,
      "with init_timeout_scene_px: a tracker without its first window after this long is dropped however "
      "little the scene moved");
    v("housekeeping_ms", housekeeping_ms, "event-time period of the idle, time-out and quality checks");
    v("min_anisotropy", min_anisotropy,
      "quality test: a feature is dropped when its window events spread along a line (ratio of the "
      "smaller to the larger eigenvalue of their covariance below this): an edge, which HASTE drifts along");
    v("max_drift_px", max_drift_px,
      "drift test: a feature is dropped when the best match of its current event window to the template of "
      "its first window lies farther than this from its state (it slid along a contour or lost its feature); "
      "0 disables the test");
    v("drift_check_ms", drift_check_ms, "event-time period of each feature's drift test");
    v("max_rotation_deg", max_rotation_deg,
      "rotation test: a feature is dropped when its patch rotation since initialization departs by more than "
      "this from the common rotation of all features (the median; a rigid scene rotates every patch alike), "
      "the sign of a tracker sliding around a curved contour; 0 disables the test");
    v("max_neighbour_disagreement_px", max_neighbour_disagreement_px,
      "neighbour-motion test: a feature is dropped when its displacement over the last neighbour_window_ms "
      "differs by more than this from the median displacement of its nearest features (a tracker creeping "
      "over a soft texture moves unlike the scene around it); 0 disables the test");
    v("neighbour_disagreement_fraction", neighbour_disagreement_fraction,
      "neighbour-motion test: the bound grows by this fraction of the length of the neighbours' median "
      "displacement (depth differences between neighbours part their image motions in proportion to it); "
      "0 keeps the bound at max_neighbour_disagreement_px");
    v("neighbour_motion_model", neighbour_motion_model,
      "neighbour-motion test: translation (the reference is the neighbours' median displacement), "
      "similarity (each neighbour's displacement is first carried to the feature through the in-plane "
      "rotation and scale change of the neighbours' pairs, their medians, so a roll or a zoom does not part "
      "neighbours) or either (dropped only when both references disagree)");
    v("neighbour_similarity_min_px", neighbour_similarity_min_px,
      "neighbour-motion test with either: the similarity reference is consulted only when the rotation and "
      "scale it fits move the feature by at least this much relative to its neighbours' mean position (a "
      "motion the translation describes keeps the translation's verdict); 0 = always");
    v("neighbour_similarity_agreement_px", neighbour_similarity_agreement_px,
      "neighbour-motion test with either: a feature the similarity reference keeps is still dropped when a "
      "neighbour's displacement carried to the feature lies farther than this from their median (neighbours "
      "on two motions, across a depth discontinuity, do not follow one similarity); 0 = off");
    v("neighbour_check_ms", neighbour_check_ms, "event-time period of the neighbour-motion test");
    v("neighbour_window_ms", neighbour_window_ms,
      "neighbour-motion test: time span of the compared displacements");
    v("neighbour_count", neighbour_count,
      "neighbour-motion test: number of nearest features whose median displacement is the reference");
    v("neighbour_radius_px", neighbour_radius_px,
      "neighbour-motion test: only features within this distance count as neighbours (at least 3 needed)");
    v("max_time_reversal_us", max_time_reversal_us,
      "events earlier than the newest seen by more than this are dropped and counted; smaller steps "
      "back are processed at the newest time");
    v("subpixel_measurements", subpixel_measurements,
      "measurements refined to the vertex of a parabola through the scores of the +-1 px hypotheses "
      "(false: the tracker's 1-px state)");
    v("subpixel_method", subpixel_method,
      "with subpixel_measurements: parabola (the vertex of the parabola through the +-1 px hypothesis scores) or "
      "template_fit (the translation that best fits the window to the template blurred by 1 px, found by "
      "Newton steps on its cubic interpolation)");
    v("rectified_tracking", rectified_tracking,
      "the trackers work on the undistorted pinhole image of the camera's intrinsics, where a patch keeps "
      "its shape across the image (false: on the raw pixels, where the lens distortion warps it)");
  }
  void validate() const;
  /// The factor on min_distance_px and neighbour_radius_px for a frontend image of width x height:
  /// diagonal / 300 px with scale_distances, else 1.
  double distanceScale(int width, int height) const {
    return scale_distances ? std::hypot(static_cast<double>(width), static_cast<double>(height)) / 300.0 : 1.0;
  }
};

}  // namespace asynevo
