#pragma once
// HASTE event-by-event patch trackers (Alzugaray & Chli, "HASTE: multi-Hypothesis Asynchronous
// Speeded-up Tracking of Events", BMVC 2020), our own implementation of the two incremental
// ("star") variants described in shared/reference/frontend.md §6:
//   HasteDifference*  score_h = -sum_pixels (That - M_h)^2       (default)
//   HasteCorrelation* score_h = (1/N) sum_i S(That, h, e_i)
// with That the template normalised to unit sum (frozen between state switches), M_h the bilinear
// splat of the N window events under hypothesis h (weight 1/N each) and S a bilinear sample.
//
// A tracker's state is (t, x, y, theta) in the image coordinates it is fed with. The 31x31 patch
// (radius 15) is centred on the state; an event is used iff it lies strictly inside the circle of
// radius 15. The window holds the N = 193 newest in-range events (ring buffer). 11 hypotheses:
// identity, +-1 px in x and y, the 4 diagonals, +-4 degrees. After every in-range event the best
// hypothesis replaces the state when (best - null) / (best - worst) > hysteresis; the state time is
// the time of the window's middle event. The template grows by alpha/N times the splat of the middle
// event under the current state on every in-range event after initialization.
//
// Everything is allocated at construction; push() never allocates. reset() reuses a tracker.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace asynevo::frontend {

constexpr float kPi = 3.14159265358979323846f;
/// An angle wrapped to (-pi, pi].
float wrapAngle(float a);

enum class TrackerResult : uint8_t {
  kOutOfRange,    ///< the event is outside the tracker's circle: ignored
  kInitializing,  ///< the event was added to the (not yet full) first window
  kRegular,       ///< used, no state change
  kStateChanged,  ///< initialization completed or the state switched to another hypothesis
};

enum class HasteVariant : uint8_t { kDifferenceStar, kCorrelationStar };

struct HasteParams {
  HasteVariant variant = HasteVariant::kCorrelationStar;
  double hysteresis = 0.05;      ///< (ref) switch threshold on the normalised score gain
  double template_update = 0.1;  ///< (ref) alpha; 0 freezes the template after initialization
};

struct TrackerState {
  int64_t t_ns = 0;
  float x = 0.f;
  float y = 0.f;
  float theta = 0.f;  ///< radians, wrapped to (-pi, pi]
};

/// One pose hypothesis around the current state.
struct Hypothesis {
  float x = 0.f, y = 0.f, theta = 0.f;
  float c = 1.f, s = 0.f;  ///< cos and sin of theta
};

class HasteTracker {
 public:
  static constexpr int kPatchSize = 31;
  static constexpr int kRadius = 15;
  static constexpr int kPatchCells = kPatchSize * kPatchSize;
  static constexpr int kWindow = 193;  ///< 1 + 2 floor(0.2 * 31 * 31 / 2) (reference texture factor 0.2)
  static constexpr int kMiddle = kWindow / 2;
  static constexpr int kHypotheses = 11;
  static constexpr float kRotationStep = 4.0f * kPi / 180.0f;

  using Patch = std::array<float, kPatchCells>;  ///< [yp * 31 + xp]

  struct WindowEvent {
    int64_t t_ns;
    float x, y;
  };

  explicit HasteTracker(const HasteParams& params);
  virtual ~HasteTracker() = default;
  HasteTracker(const HasteTracker&) = delete;
  HasteTracker& operator=(const HasteTracker&) = delete;

  /// Restarts the tracker at a seed pose; nothing allocated.
  void reset(int64_t t_ns, float x, float y, float theta = 0.f);

  /// Feeds one event (image coordinates of the tracker's frame).
  TrackerResult push(int64_t t_ns, float x, float y) {
    const float dx = x - state_.x, dy = y - state_.y;
    if (!(dx * dx + dy * dy < float(kRadius * kRadius))) return TrackerResult::kOutOfRange;
    return pushInRange(t_ns, x, y);
  }
  /// push() of an event the caller already found in range (inRange(), or the same test on a copy of
  /// state().x, state().y).
  TrackerResult pushInRange(int64_t t_ns, float x, float y);
  bool inRange(float x, float y) const {
    const float dx = x - state_.x, dy = y - state_.y;
    return dx * dx + dy * dy < float(kRadius * kRadius);
  }

  const TrackerState& state() const { return state_; }
  bool initialized() const { return initialized_; }
  /// False once the template has no mass (cannot normalise): the tracker must be dropped.
  bool healthy() const { return healthy_; }
  const HasteParams& params() const { return params_; }

  // ---- introspection for quality tests and unit tests ----------------------------------------
  const std::array<Hypothesis, kHypotheses>& hypotheses() const { return hyps_; }
  const std::array<double, kHypotheses>& scores() const { return scores_; }
  /// The evolving template (not normalised).
  const Patch& templatePatch() const { return template_; }
  /// The normalised template the scores currently use (frozen at the last switch).
  const Patch& normalizedTemplate() const { return normalized_; }
  /// The normalised template of the first window (built at initialization, never updated): a reference
  /// the tracker cannot pull along.
  const Patch& firstTemplate() const { return first_template_; }
  /// Mean bilinear sample of `tmpl` at the window events mapped into the patch under the pose
  /// (x, y, theta): the HasteCorrelation score of that pose against that template. With stride k only
  /// every k-th window event is sampled (the mean is scaled accordingly).
  double matchScore(const Patch& tmpl, float x, float y, float theta, int stride = 1) const;
  /// Drift test against the first template: the pose of the best match of the current window to
  /// firstTemplate(), searched by hill climbing on the hypothesis grid (1 px, kRotationStep) from the
  /// previous check's offset; returns its translation from the current state in px. A tracker that slid
  /// along a contour, or lost its feature, is far from where its first window says it should be.
  float firstTemplateDrift();
  /// matchScore(tmpl, ...) with the given stride at the 9 poses (x + ox, y + oy, angleAfter(turns)) for the
  /// 9 translation offsets of the hypotheses (identity first), in one pass over the window.
  void matchScoresTranslated(const Patch& tmpl, float x, float y, int turns, int stride, double* out) const;
  /// The window events, oldest first (fewer than kWindow while initializing).
  int windowSize() const { return count_; }
  const WindowEvent& windowEvent(int i) const { return window_[(head_ + i) % kWindow]; }
  /// Ratio of the smaller to the larger eigenvalue of the covariance of the window events' positions
  /// (1 = isotropic spread, ~0 = events on a line: an edge, where the tracker can slide).
  float windowAnisotropy() const;
  /// Sub-pixel offset of the best match from the state, x and y apart: the vertex of the parabola
  /// through the scores of the −1, 0, +1 px hypotheses, δ = (s₋ − s₊) / (2 (s₋ − 2 s₀ + s₊)), clamped
  /// to ±0.5 px; 0 where the scores are not concave (no maximum between the neighbours).
  void subpixelOffset(float& dx, float& dy) const;
  /// Sub-pixel offset of the feature from the state by a continuous fit: the translation u that maximizes
  /// the mean over the window events of the normalized template, blurred by a Gaussian (sigma 1 px) and
  /// interpolated by Keys' cubic convolution (C1-smooth, unlike the bilinear scores, whose maxima lie on
  /// the grid), found by Newton steps of at most 0.5 px from the state; false (dx = dy = 0) when the fit
  /// ends more than kMaxFitOffset px away or the template has no mass.
  bool subpixelFit(float& dx, float& dy) const;
  static constexpr float kMaxFitOffset = 3.0f;
  /// In-range events since the last state change, and state changes since reset.
  uint32_t eventsSinceChange() const { return events_since_change_; }
  uint32_t stateChanges() const { return state_changes_; }

  /// Patch coordinates of an image point under a hypothesis (reference §6.1).
  static void toPatch(const Hypothesis& h, float ex, float ey, float& xp, float& yp) {
    const float dx = ex - h.x, dy = ey - h.y;
    xp = dx * h.c + dy * h.s + float(kRadius);
    yp = -dx * h.s + dy * h.c + float(kRadius);
  }
  /// Bilinear stencil: base cell index and the 4 weights; false outside [0, 30) x [0, 30).
  static bool stencil(float xp, float yp, int& base, float w[4]) {
    // Valid for 0 <= xp < 30 and 0 <= yp < 30 (the 2x2 stencil needs the +1 neighbour).
    if (!(xp >= 0.f && yp >= 0.f && xp < float(kPatchSize - 1) && yp < float(kPatchSize - 1))) return false;
    const int x0 = static_cast<int>(xp), y0 = static_cast<int>(yp);
    const float fx = xp - float(x0), fy = yp - float(y0);
    base = y0 * kPatchSize + x0;
    w[0] = (1.f - fx) * (1.f - fy);
    w[1] = fx * (1.f - fy);
    w[2] = (1.f - fx) * fy;
    w[3] = fx * fy;
    return true;
  }
  static void splat(Patch& p, float xp, float yp, float weight) {
    int base;
    float w[4];
    if (!stencil(xp, yp, base, w)) return;
    p[base] += weight * w[0];
    p[base + 1] += weight * w[1];
    p[base + kPatchSize] += weight * w[2];
    p[base + kPatchSize + 1] += weight * w[3];
  }
  static float sample(const Patch& p, float xp, float yp) {
    int base;
    float w[4];
    if (!stencil(xp, yp, base, w)) return 0.f;
    return w[0] * p[base] + w[1] * p[base + 1] + w[2] * p[base + kPatchSize] + w[3] * p[base + kPatchSize + 1];
  }
  /// sample(tmpl, ...) at an image point under each of the 11 hypotheses (out[h]; out[11] is padding).
  /// While the state angle is 0 the 9 translations differ from the identity by whole patch cells, so
  /// one bilinear stencil serves all 9 (same values as 9 calls of sample()).
  void sampleHypotheses(const Patch& tmpl, float ex, float ey, float* out) const;

 protected:
  /// Recomputes every score from the current window and normalized template.
  virtual void rebuildScores() = 0;
  /// Incremental score update: `added` entered the window at storage index `index` (window_[index]),
  /// where `evicted` left it.
  virtual void updateScores(int index, const WindowEvent& added, const WindowEvent& evicted) = 0;

  /// Patch coordinates of an image point under every hypothesis (structure-of-arrays, vectorizable).
  void patchCoordinates(float ex, float ey, float* xp, float* yp) const {
    for (int h = 0; h < kPadded; ++h) {
      const float dx = ex - hx_[h], dy = ey - hy_[h];
      xp[h] = dx * hc_[h] + dy * hs_[h] + float(kRadius);
      yp[h] = -dx * hs_[h] + dy * hc_[h] + float(kRadius);
    }
  }
  static constexpr int kPadded = 12;  ///< hypotheses padded for SIMD
  static constexpr int kTranslations = 9;  ///< hypotheses 0..8: identity and the 8 one-pixel shifts

  std::array<Hypothesis, kHypotheses> hyps_{};
  alignas(32) float hx_[kPadded] = {}, hy_[kPadded] = {}, hc_[kPadded] = {}, hs_[kPadded] = {};
  std::array<double, kHypotheses> scores_{};
  bool axis_aligned_ = true;  ///< state angle exactly 0 (sampleHypotheses' shared-stencil path)
  float theta0_ = 0.f;        ///< seed angle
  int turns_ = 0;             ///< rotation steps since the seed, in (-kTurnsPerRevolution/2, kTurnsPerRevolution/2]
  static constexpr int kTurnsPerRevolution = 90;  ///< 360 / 4 degrees
  /// Angle of the seed plus `turns` rotation steps, wrapped (exact multiples of the step: no drift).
  float angleAfter(int turns) const { return wrapAngle(theta0_ + float(turns) * kRotationStep); }
  bool alignedAfter(int turns) const { return theta0_ == 0.f && turns % kTurnsPerRevolution == 0; }
  Patch normalized_{};
  std::vector<WindowEvent> window_;  ///< ring buffer of kWindow events, allocated once
  int head_ = 0;                     ///< index of the oldest event
  int count_ = 0;

 private:
  void generateHypotheses();
  void initializeTemplate();
  bool normalizeTemplate();
  void addMoments(const WindowEvent& e, double sign);

  HasteParams params_;
  TrackerState state_;
  bool initialized_ = false;
  bool healthy_ = true;
  Patch template_{};
  Patch first_template_{};
  int drift_dx_ = 0, drift_dy_ = 0, drift_dth_ = 0;  ///< best first-template offset at the last check
  uint32_t events_since_change_ = 0;
  uint32_t state_changes_ = 0;
  double moment_[5] = {0, 0, 0, 0, 0};  ///< sums of x, y, xx, xy, yy over the window (relative to origin_)
  float origin_x_ = 0.f, origin_y_ = 0.f;
};

/// HasteDifference*: keeps the 11 difference patches D_h = That - M_h and updates the squared
/// norms of the 2x2 blocks an added or evicted event touches. The patches are stored interleaved,
/// [cell][hypothesis], so the 11 stencils of one event (at most 1 px apart) share cache lines.
class HasteDifferenceStar final : public HasteTracker {
 public:
  explicit HasteDifferenceStar(const HasteParams& params);
  /// Entry of the difference patch of hypothesis h (for tests).
  float difference(int h, int cell) const { return diff_[static_cast<std::size_t>(cell) * kHypotheses + h]; }

 protected:
  void rebuildScores() override;
  void updateScores(int index, const WindowEvent& added, const WindowEvent& evicted) override;

 private:
  std::vector<float> diff_;  ///< kPatchCells x kHypotheses, allocated once
};

/// HasteCorrelation*: mean bilinear sample of the frozen normalized template at the window events.
/// The 11 samples of every window event are kept beside the window (same storage index): the template
/// and the hypotheses are frozen between switches, and every switch resamples the whole window, so an
/// evicted event's samples are the ones it added (not computed again).
class HasteCorrelationStar final : public HasteTracker {
 public:
  explicit HasteCorrelationStar(const HasteParams& params);

 protected:
  void rebuildScores() override;
  void updateScores(int index, const WindowEvent& added, const WindowEvent& evicted) override;

 private:
  std::vector<float> samples_;  ///< kWindow x kPadded: samples of window_[i] at [i * kPadded], allocated once
};

/// Builds the tracker of a variant.
std::unique_ptr<HasteTracker> makeHasteTracker(const HasteParams& params);

/// Scores of every hypothesis computed from scratch (no incremental state) from a tracker's
/// window, hypotheses and normalized template: the definition the star variants must agree with.
std::array<double, HasteTracker::kHypotheses> hasteScoresFromScratch(const HasteTracker& tracker);

}  // namespace asynevo::frontend
