// HASTE trackers (Alzugaray & Chli, BMVC 2020): algorithm as restated in
// shared/reference/frontend.md §6; our own implementation (ring buffer, explicit NaN guards,
// wrapped theta, no allocation after construction).
#include "asynevo/frontend/haste_tracker.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace asynevo::frontend {

namespace {

constexpr float kInvWindow = 1.0f / HasteTracker::kWindow;
constexpr int kStencilOffset[4] = {0, 1, HasteTracker::kPatchSize, HasteTracker::kPatchSize + 1};

/// The bilinear samples of `tmpl` for the 9 translation hypotheses (kOffsets order) of one stencil
/// (cell x0, y0 of the identity, weights w0..w3), when every one lies inside the patch with room for a
/// 4-wide row (1 <= x0 <= kPatchSize - 4, 1 <= y0 <= kPatchSize - 3); false otherwise (nothing written).
/// Each value is w0 t00 + w1 t01 + w2 t10 + w3 t11 evaluated in that order, as sample() does: the three
/// hypotheses of one row are lanes of one vector (no fused or reordered arithmetic), so the results
/// are the same floats.
inline bool interiorTranslationSamples(const float* tmpl, int x0, int y0, float w0, float w1, float w2, float w3,
                                       float* out) {
  constexpr int kP = HasteTracker::kPatchSize;
  if (x0 < 1 || y0 < 1 || x0 > kP - 4 || y0 > kP - 3) return false;
  // Rows yh = y0 - oy for oy = 1, 0, -1; lanes xh = x0 - ox for ox = 1, 0, -1 (and one unused lane).
  alignas(16) float rows[3][4];
  const float* base = tmpl + (y0 - 1) * kP + (x0 - 1);
#if defined(__SSE2__)
  const __m128 v0 = _mm_set1_ps(w0), v1 = _mm_set1_ps(w1), v2 = _mm_set1_ps(w2), v3 = _mm_set1_ps(w3);
  for (int r = 0; r < 3; ++r) {
    const float* t = base + r * kP;
    const __m128 s = _mm_add_ps(
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(v0, _mm_loadu_ps(t)), _mm_mul_ps(v1, _mm_loadu_ps(t + 1))),
                   _mm_mul_ps(v2, _mm_loadu_ps(t + kP))),
        _mm_mul_ps(v3, _mm_loadu_ps(t + kP + 1)));
    _mm_store_ps(rows[r], s);
  }
#else
  for (int r = 0; r < 3; ++r) {
    const float* t = base + r * kP;
    for (int j = 0; j < 3; ++j) rows[r][j] = w0 * t[j] + w1 * t[j + 1] + w2 * t[j + kP] + w3 * t[j + kP + 1];
  }
#endif
  // kOffsets: 0 (0,0), 1 (1,0), 2 (-1,0), 3 (0,1), 4 (0,-1), 5 (1,1), 6 (1,-1), 7 (-1,1), 8 (-1,-1).
  out[0] = rows[1][1];
  out[1] = rows[1][0];
  out[2] = rows[1][2];
  out[3] = rows[0][1];
  out[4] = rows[2][1];
  out[5] = rows[0][0];
  out[6] = rows[2][0];
  out[7] = rows[0][2];
  out[8] = rows[2][2];
  return true;
}

}  // namespace

float wrapAngle(float a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

HasteTracker::HasteTracker(const HasteParams& params) : window_(kWindow), params_(params) {}

void HasteTracker::reset(int64_t t_ns, float x, float y, float theta) {
  state_ = TrackerState{t_ns, x, y, wrapAngle(theta)};
  theta0_ = state_.theta;
  turns_ = 0;
  initialized_ = false;
  healthy_ = true;
  head_ = 0;
  count_ = 0;
  events_since_change_ = 0;
  state_changes_ = 0;
  std::fill(std::begin(moment_), std::end(moment_), 0.0);
  drift_dx_ = drift_dy_ = drift_dth_ = 0;
  origin_x_ = x;
  origin_y_ = y;
  generateHypotheses();
  scores_.fill(0.0);
}

namespace {
// Hypotheses as offsets from the state: (x px, y px, rotation steps); the 9 translations come first.
constexpr int kOffsets[HasteTracker::kHypotheses][3] = {{0, 0, 0},  {1, 0, 0},   {-1, 0, 0}, {0, 1, 0},
                                                        {0, -1, 0}, {1, 1, 0},   {1, -1, 0}, {-1, 1, 0},
                                                        {-1, -1, 0}, {0, 0, 1}, {0, 0, -1}};
}  // namespace

void HasteTracker::sampleHypotheses(const Patch& tmpl, float ex, float ey, float* out) const {
  if (!axis_aligned_) {
    alignas(32) float xp[kPadded], yp[kPadded];
    patchCoordinates(ex, ey, xp, yp);
    for (int h = 0; h < kHypotheses; ++h) out[h] = sample(tmpl, xp[h], yp[h]);
    out[kHypotheses] = 0.f;
    return;
  }
  // Angle 0: hypothesis (ox, oy) maps the point to (xp - ox, yp - oy): same fractions, cells shifted.
  const float xp = ex - state_.x + float(kRadius), yp = ey - state_.y + float(kRadius);
  int x0 = static_cast<int>(xp), y0 = static_cast<int>(yp);
  x0 -= xp < float(x0) ? 1 : 0;  // floor (window events can lie just outside the patch after a switch)
  y0 -= yp < float(y0) ? 1 : 0;
  const float fx = xp - float(x0), fy = yp - float(y0);
  const float w0 = (1.f - fx) * (1.f - fy), w1 = fx * (1.f - fy), w2 = (1.f - fx) * fy, w3 = fx * fy;
  if (!interiorTranslationSamples(tmpl.data(), x0, y0, w0, w1, w2, w3, out)) {
    for (int h = 0; h < kTranslations; ++h) {
      const int xh = x0 - kOffsets[h][0], yh = y0 - kOffsets[h][1];
      // Same condition as stencil(): 0 <= xh + fx < kPatchSize - 1 with 0 <= fx < 1.
      if (static_cast<unsigned>(xh) > unsigned(kPatchSize - 2) ||
          static_cast<unsigned>(yh) > unsigned(kPatchSize - 2)) {
        out[h] = 0.f;
        continue;
      }
      const float* t = &tmpl[static_cast<std::size_t>(yh * kPatchSize + xh)];
      out[h] = w0 * t[0] + w1 * t[1] + w2 * t[kPatchSize] + w3 * t[kPatchSize + 1];
    }
  }
  for (int h = kTranslations; h < kHypotheses; ++h) {
    float xh, yh;
    toPatch(hyps_[h], ex, ey, xh, yh);
    out[h] = sample(tmpl, xh, yh);
  }
  out[kHypotheses] = 0.f;
}

void HasteTracker::generateHypotheses() {
  for (int h = 0; h < kHypotheses; ++h) {
    Hypothesis& hy = hyps_[h];
    hy.x = state_.x + float(kOffsets[h][0]);
    hy.y = state_.y + float(kOffsets[h][1]);
    hy.theta = angleAfter(turns_ + kOffsets[h][2]);
    hy.c = std::cos(hy.theta);
    hy.s = std::sin(hy.theta);
  }
  axis_aligned_ = alignedAfter(turns_);
  for (int h = 0; h < kPadded; ++h) {
    const Hypothesis& hy = hyps_[h < kHypotheses ? h : 0];
    hx_[h] = hy.x;
    hy_[h] = hy.y;
    hc_[h] = hy.c;
    hs_[h] = hy.s;
  }
}

void HasteTracker::initializeTemplate() {
  template_.fill(0.f);
  for (int i = 0; i < count_; ++i) {
    const WindowEvent& e = windowEvent(i);
    float xp, yp;
    toPatch(hyps_[0], e.x, e.y, xp, yp);
    splat(template_, xp, yp, kInvWindow);
  }
}

bool HasteTracker::normalizeTemplate() {
  double sum = 0;
  for (float v : template_) sum += v;
  if (!(sum > 1e-12) || !std::isfinite(sum)) return false;
  const float inv = static_cast<float>(1.0 / sum);
  for (int i = 0; i < kPatchCells; ++i) normalized_[i] = template_[i] * inv;
  return true;
}

void HasteTracker::addMoments(const WindowEvent& e, double sign) {
  const double x = e.x - origin_x_, y = e.y - origin_y_;
  moment_[0] += sign * x;
  moment_[1] += sign * y;
  moment_[2] += sign * x * x;
  moment_[3] += sign * x * y;
  moment_[4] += sign * y * y;
}

float HasteTracker::windowAnisotropy() const {
  if (count_ < 2) return 0.f;
  const double n = count_;
  const double mx = moment_[0] / n, my = moment_[1] / n;
  const double a = moment_[2] / n - mx * mx, b = moment_[3] / n - mx * my, c = moment_[4] / n - my * my;
  const double half_trace = 0.5 * (a + c);
  const double root = std::sqrt(std::max(0.0, 0.25 * (a - c) * (a - c) + b * b));
  const double large = half_trace + root, small = half_trace - root;
  if (!(large > 1e-12)) return 0.f;
  return static_cast<float>(std::max(0.0, small) / large);
}

double HasteTracker::matchScore(const Patch& tmpl, float x, float y, float theta, int stride) const {
  const float c = std::cos(theta), sn = std::sin(theta);
  // The sum does not depend on the order: walk the ring buffer's storage directly (entries [0, count_)
  // are the window both while initializing and once full).
  float sum = 0.f;
  for (int i = 0; i < count_; i += stride) {
    const WindowEvent& e = window_[static_cast<std::size_t>(i)];
    const float dx = e.x - x, dy = e.y - y;
    sum += sample(tmpl, dx * c + dy * sn + float(kRadius), -dx * sn + dy * c + float(kRadius));
  }
  return double(sum) * stride * kInvWindow;
}

void HasteTracker::matchScoresTranslated(const Patch& tmpl, float x, float y, int turns, int stride,
                                         double* out) const {
  float sums[kTranslations] = {};
  if (alignedAfter(turns)) {
    // Angle 0: offset (ox, oy) maps an event to the identity's patch point shifted by (-ox, -oy) cells.
    for (int i = 0; i < count_; i += stride) {
      const WindowEvent& e = window_[static_cast<std::size_t>(i)];
      const float xp = e.x - x + float(kRadius), yp = e.y - y + float(kRadius);
      int x0 = static_cast<int>(xp), y0 = static_cast<int>(yp);
      x0 -= xp < float(x0) ? 1 : 0;
      y0 -= yp < float(y0) ? 1 : 0;
      const float fx = xp - float(x0), fy = yp - float(y0);
      const float w0 = (1.f - fx) * (1.f - fy), w1 = fx * (1.f - fy), w2 = (1.f - fx) * fy, w3 = fx * fy;
      float v[kTranslations];
      if (interiorTranslationSamples(tmpl.data(), x0, y0, w0, w1, w2, w3, v)) {
        for (int h = 0; h < kTranslations; ++h) sums[h] += v[h];
        continue;
      }
      for (int h = 0; h < kTranslations; ++h) {
        const int xh = x0 - kOffsets[h][0], yh = y0 - kOffsets[h][1];
        if (static_cast<unsigned>(xh) > unsigned(kPatchSize - 2) ||
            static_cast<unsigned>(yh) > unsigned(kPatchSize - 2))
          continue;
        const float* t = &tmpl[static_cast<std::size_t>(yh * kPatchSize + xh)];
        sums[h] += w0 * t[0] + w1 * t[1] + w2 * t[kPatchSize] + w3 * t[kPatchSize + 1];
      }
    }
  } else {
    // Offset (ox, oy) moves every event's patch point by the same rotated vector.
    const float theta = angleAfter(turns), c = std::cos(theta), sn = std::sin(theta);
    float sx[kTranslations], sy[kTranslations];
    for (int h = 0; h < kTranslations; ++h) {
      const float ox = float(kOffsets[h][0]), oy = float(kOffsets[h][1]);
      sx[h] = ox * c + oy * sn;
      sy[h] = -ox * sn + oy * c;
    }
    for (int i = 0; i < count_; i += stride) {
      const WindowEvent& e = window_[static_cast<std::size_t>(i)];
      const float dx = e.x - x, dy = e.y - y;
      const float xp = dx * c + dy * sn + float(kRadius), yp = -dx * sn + dy * c + float(kRadius);
      for (int h = 0; h < kTranslations; ++h) sums[h] += sample(tmpl, xp - sx[h], yp - sy[h]);
    }
  }
  for (int h = 0; h < kTranslations; ++h) out[h] = double(sums[h]) * stride * kInvWindow;
}

float HasteTracker::firstTemplateDrift() {
  if (!initialized_) return 0.f;
  // Every second window event: half the cost, and the simulated accuracy did not change measurably.
  constexpr int kStride = 2;
  // Scores of visited offsets, so a hill-climbing step never evaluates one twice.
  constexpr int kReach = 6, kSide = 2 * kReach + 1, kTurns = 5;
  std::array<double, kSide * kSide * kTurns> cache;
  cache.fill(std::numeric_limits<double>::quiet_NaN());
  auto at = [&](int dx, int dy, int dth) -> double& {
    return cache[static_cast<std::size_t>(((dth + kTurns / 2) * kSide + dy + kReach) * kSide + dx + kReach)];
  };
  auto inReach = [&](int dx, int dy, int dth) {
    return std::abs(dx) <= kReach && std::abs(dy) <= kReach && std::abs(dth) <= kTurns / 2;
  };
  // The 3x3 translations around (cx, cy) at rotation cth, in one pass when any of them is missing.
  auto block = [&](int cx, int cy, int cth) {
    bool missing = false;
    for (int h = 0; h < kTranslations; ++h) {
      const int x = cx + kOffsets[h][0], y = cy + kOffsets[h][1];
      missing = missing || (inReach(x, y, cth) && std::isnan(at(x, y, cth)));
    }
    if (!missing) return;
    double v[kTranslations];
    matchScoresTranslated(first_template_, state_.x + float(cx), state_.y + float(cy), turns_ + cth, kStride, v);
    for (int h = 0; h < kTranslations; ++h) {
      const int x = cx + kOffsets[h][0], y = cy + kOffsets[h][1];
      if (inReach(x, y, cth) && std::isnan(at(x, y, cth))) at(x, y, cth) = v[h];
    }
  };
  auto single = [&](int dx, int dy, int dth) {
    double& v = at(dx, dy, dth);
    if (std::isnan(v))
      v = matchScore(first_template_, state_.x + float(dx), state_.y + float(dy), angleAfter(turns_ + dth),
                     kStride);
    return v;
  };
  int bx = std::clamp(drift_dx_, -kReach, kReach), by = std::clamp(drift_dy_, -kReach, kReach);
  int bth = std::clamp(drift_dth_, -kTurns / 2, kTurns / 2);
  block(bx, by, bth);
  double best = at(bx, by, bth);
  // Steepest ascent over 10 neighbours (the 8 translations by 1 px, the 2 rotations by one step) until
  // none is better. (The 26 of the full 3x3x3 cube cost 2.6x as much for no measurable gain.) The 8
  // translations are scored together (matchScoresTranslated), the 2 rotations one by one.
  for (bool moved = true; moved;) {
    moved = false;
    const int cx = bx, cy = by, cth = bth;
    block(cx, cy, cth);
    auto consider = [&](int x, int y, int th, double v) {
      if (v > best) {
        best = v;
        bx = x;
        by = y;
        bth = th;
        moved = true;
      }
    };
    for (int h = 1; h < kTranslations; ++h) {
      const int x = cx + kOffsets[h][0], y = cy + kOffsets[h][1];
      if (inReach(x, y, cth)) consider(x, y, cth, at(x, y, cth));
    }
    for (int th : {cth + 1, cth - 1})
      if (inReach(cx, cy, th)) consider(cx, cy, th, single(cx, cy, th));
  }
  drift_dx_ = bx;
  drift_dy_ = by;
  drift_dth_ = bth;
  return std::hypot(float(bx), float(by));
}

TrackerResult HasteTracker::pushInRange(int64_t t_ns, float x, float y) {
  const WindowEvent e{t_ns, x, y};
  if (!initialized_) {
    assert(count_ < kWindow && head_ == 0);
    window_[count_++] = e;
    addMoments(e, 1.0);
    if (count_ < kWindow) return TrackerResult::kInitializing;
    initializeTemplate();
    if (!normalizeTemplate()) {
      healthy_ = false;
      return TrackerResult::kRegular;
    }
    first_template_ = normalized_;
    rebuildScores();
    initialized_ = true;
    state_.t_ns = windowEvent(kMiddle).t_ns;
    ++state_changes_;
    events_since_change_ = 0;
    return TrackerResult::kStateChanged;
  }
  if (!healthy_) return TrackerResult::kRegular;

  // Slide the window: the oldest event leaves, the new one enters.
  const int index = head_;
  const WindowEvent evicted = window_[index];
  window_[index] = e;
  head_ = head_ + 1 == kWindow ? 0 : head_ + 1;
  addMoments(e, 1.0);
  addMoments(evicted, -1.0);
  updateScores(index, e, evicted);

  // Hysteresis decision (reference §6.4) with explicit guards against NaN and all-equal scores.
  const double null_score = scores_[0];
  int best = 0;
  double worst = null_score;
  for (int h = 1; h < kHypotheses; ++h) {
    if (scores_[h] > scores_[best]) best = h;
    worst = std::min(worst, scores_[h]);
  }
  bool switched = false;
  if (best != 0) {
    const double gain = scores_[best] - null_score;
    const double range = scores_[best] - worst;
    switched = std::isfinite(gain) && std::isfinite(range) && range > 0 && gain > params_.hysteresis * range;
  }
  ++events_since_change_;
  if (switched) {
    state_.x = hyps_[best].x;
    state_.y = hyps_[best].y;
    turns_ += kOffsets[best][2];
    if (turns_ > kTurnsPerRevolution / 2) turns_ -= kTurnsPerRevolution;
    if (turns_ <= -kTurnsPerRevolution / 2) turns_ += kTurnsPerRevolution;
    state_.theta = angleAfter(turns_);
    generateHypotheses();
    if (!normalizeTemplate()) {
      healthy_ = false;
      return TrackerResult::kRegular;
    }
    rebuildScores();
    ++state_changes_;
    events_since_change_ = 0;
  }
  const WindowEvent& middle = windowEvent(kMiddle);
  if (params_.template_update > 0) {
    float xp, yp;
    toPatch(hyps_[0], middle.x, middle.y, xp, yp);
    splat(template_, xp, yp, static_cast<float>(params_.template_update) * kInvWindow);
  }
  state_.t_ns = middle.t_ns;
  return switched ? TrackerResult::kStateChanged : TrackerResult::kRegular;
}

namespace {
// Vertex of the parabola through (−1, minus), (0, zero), (+1, plus); 0 unless it is a maximum.
float parabolaVertex(double minus, double zero, double plus) {
  const double curvature = minus - 2.0 * zero + plus;
  if (!(curvature < 0.0)) return 0.f;
  const double offset = 0.5 * (minus - plus) / curvature;
  return static_cast<float>(std::clamp(offset, -0.5, 0.5));
}
}  // namespace

void HasteTracker::subpixelOffset(float& dx, float& dy) const {
  // kOffsets: 1 = +x, 2 = −x, 3 = +y, 4 = −y (image axes).
  dx = parabolaVertex(scores_[2], scores_[0], scores_[1]);
  dy = parabolaVertex(scores_[4], scores_[0], scores_[3]);
}

namespace {
// Keys' cubic convolution kernel (a = -0.5; R. Keys, "Cubic convolution interpolation for digital image
// processing", IEEE TASSP 1981) at the 4 taps -1, 0, 1, 2 around a fraction f, with its first and second
// derivatives in f.
void keysWeights(double f, double w[4], double dw[4], double ddw[4]) {
  const double f2 = f * f, f3 = f2 * f;
  w[0] = -0.5 * f3 + f2 - 0.5 * f;
  w[1] = 1.5 * f3 - 2.5 * f2 + 1;
  w[2] = -1.5 * f3 + 2 * f2 + 0.5 * f;
  w[3] = 0.5 * f3 - 0.5 * f2;
  dw[0] = -1.5 * f2 + 2 * f - 0.5;
  dw[1] = 4.5 * f2 - 5 * f;
  dw[2] = -4.5 * f2 + 4 * f + 0.5;
  dw[3] = 1.5 * f2 - f;
  ddw[0] = -3 * f + 2;
  ddw[1] = 9 * f - 5;
  ddw[2] = -9 * f + 4;
  ddw[3] = 3 * f - 1;
}

/// Value, gradient and Hessian of the cubic interpolation of a patch (zero outside it) at (x, y); false
/// where no tap is inside.
struct CubicSample {
  double v = 0, gx = 0, gy = 0, hxx = 0, hxy = 0, hyy = 0;
};
bool cubicSample(const HasteTracker::Patch& t, double x, double y, CubicSample& out) {
  constexpr int kP = HasteTracker::kPatchSize;
  if (!(x > -1 && y > -1 && x < kP && y < kP)) return false;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  double wx[4], dwx[4], ddwx[4], wy[4], dwy[4], ddwy[4];
  keysWeights(x - x0, wx, dwx, ddwx);
  keysWeights(y - y0, wy, dwy, ddwy);
  out = CubicSample{};
  for (int j = 0; j < 4; ++j) {
    const int yy = y0 - 1 + j;
    if (yy < 0 || yy >= kP) continue;
    double rv = 0, rd = 0, rdd = 0;
    for (int i = 0; i < 4; ++i) {
      const int xx = x0 - 1 + i;
      if (xx < 0 || xx >= kP) continue;
      const double v = t[static_cast<std::size_t>(yy * kP + xx)];
      rv += wx[i] * v;
      rd += dwx[i] * v;
      rdd += ddwx[i] * v;
    }
    out.v += wy[j] * rv;
    out.gx += wy[j] * rd;
    out.gy += dwy[j] * rv;
    out.hxx += wy[j] * rdd;
    out.hxy += dwy[j] * rd;
    out.hyy += ddwy[j] * rv;
  }
  return true;
}

/// Separable Gaussian blur, sigma 1 px, truncated at 4 px, zero outside the patch.
void blurPatch(const HasteTracker::Patch& in, HasteTracker::Patch& out) {
  constexpr int kP = HasteTracker::kPatchSize;
  float k[9];
  float sum = 0;
  for (int i = -4; i <= 4; ++i) sum += k[i + 4] = std::exp(-0.5f * float(i * i));
  for (float& v : k) v /= sum;
  HasteTracker::Patch rows{};
  for (int y = 0; y < kP; ++y)
    for (int x = 0; x < kP; ++x) {
      float v = 0;
      for (int i = std::max(-4, -x); i <= std::min(4, kP - 1 - x); ++i) v += k[i + 4] * in[y * kP + x + i];
      rows[y * kP + x] = v;
    }
  for (int y = 0; y < kP; ++y)
    for (int x = 0; x < kP; ++x) {
      float v = 0;
      for (int i = std::max(-4, -y); i <= std::min(4, kP - 1 - y); ++i) v += k[i + 4] * rows[(y + i) * kP + x];
      out[y * kP + x] = v;
    }
}
}  // namespace

bool HasteTracker::subpixelFit(float& dx, float& dy) const {
  dx = dy = 0.f;
  if (!initialized_ || count_ == 0) return false;
  Patch blurred;
  blurPatch(normalized_, blurred);
  const double t_max = *std::max_element(blurred.begin(), blurred.end());
  if (!(t_max > 0)) return false;
  // Patch point of event e for an offset u of the feature from the state: p = R(theta) (e - s - u) + R.
  const double c = hc_[0], sn = hs_[0];
  // Mean template value over the window at offset u; with g and h also its gradient and Hessian in u.
  auto evaluate = [&](double ux, double uy, Eigen::Vector2d* g, Eigen::Matrix2d* h) {
    double f = 0, gx = 0, gy = 0, hxx = 0, hxy = 0, hyy = 0;
    for (int i = 0; i < count_; ++i) {
      const WindowEvent& e = window_[static_cast<std::size_t>(i)];
      const double ex = e.x - state_.x - ux, ey = e.y - state_.y - uy;
      CubicSample cs;
      if (!cubicSample(blurred, c * ex + sn * ey + kRadius, -sn * ex + c * ey + kRadius, cs)) continue;
      f += cs.v;
      if (g == nullptr) continue;
      gx += cs.gx;
      gy += cs.gy;
      hxx += cs.hxx;
      hxy += cs.hxy;
      hyy += cs.hyy;
    }
    if (g != nullptr) {
      // dp/du = -R(theta): the gradient is -R^T grad T, the Hessian R^T H_T R.
      Eigen::Matrix2d rot;
      rot << c, sn, -sn, c;
      *g = -rot.transpose() * Eigen::Vector2d(gx, gy) / count_;
      Eigen::Matrix2d ht;
      ht << hxx, hxy, hxy, hyy;
      *h = rot.transpose() * ht * rot / count_;
    }
    return f / count_;
  };
  double ux = 0, uy = 0;
  Eigen::Vector2d g;
  Eigen::Matrix2d h;
  double f = evaluate(ux, uy, &g, &h);
  for (int iteration = 0; iteration < 6; ++iteration) {
    // Newton step on the Hessian with its eigenvalues held below -0.01 t_max (a maximum is sought), at
    // most 0.5 px long, halved until the mean rises (at most 5 times).
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(h);
    const Eigen::Vector2d ev = es.eigenvalues().cwiseMin(-0.01 * t_max);
    Eigen::Vector2d step = -(es.eigenvectors() * ev.cwiseInverse().asDiagonal() * es.eigenvectors().transpose()) * g;
    if (!step.allFinite()) return false;
    if (step.norm() > 0.5) step *= 0.5 / step.norm();
    bool improved = false;
    for (int halving = 0; halving < 5 && !improved; ++halving, step *= 0.5) {
      const double fq = evaluate(ux + step.x(), uy + step.y(), nullptr, nullptr);
      if (fq > f) {
        ux += step.x();
        uy += step.y();
        f = fq;
        improved = true;
      }
    }
    if (!improved || step.norm() < 1e-3) break;  // (step was halved once more after the accepted one)
    f = evaluate(ux, uy, &g, &h);
  }
  if (!(std::hypot(ux, uy) <= kMaxFitOffset)) return false;
  dx = static_cast<float>(ux);
  dy = static_cast<float>(uy);
  return true;
}

// ---- HasteDifference* ----------------------------------------------------------------------------

HasteDifferenceStar::HasteDifferenceStar(const HasteParams& params)
    : HasteTracker(params), diff_(static_cast<std::size_t>(kPatchCells) * kHypotheses) {}

void HasteDifferenceStar::rebuildScores() {
  for (int c = 0; c < kPatchCells; ++c)
    std::fill_n(&diff_[static_cast<std::size_t>(c) * kHypotheses], kHypotheses, normalized_[c]);
  alignas(32) float xp[kPadded], yp[kPadded];
  for (int i = 0; i < count_; ++i) {
    const WindowEvent& e = windowEvent(i);
    patchCoordinates(e.x, e.y, xp, yp);
    for (int h = 0; h < kHypotheses; ++h) {
      float w[4];
      int base;
      if (!stencil(xp[h], yp[h], base, w)) continue;
      for (int k = 0; k < 4; ++k)
        diff_[static_cast<std::size_t>(base + kStencilOffset[k]) * kHypotheses + h] -= w[k] * kInvWindow;
    }
  }
  std::array<double, kHypotheses> sums{};
  for (int c = 0; c < kPatchCells; ++c) {
    const float* d = &diff_[static_cast<std::size_t>(c) * kHypotheses];
    for (int h = 0; h < kHypotheses; ++h) sums[h] += double(d[h]) * double(d[h]);
  }
  for (int h = 0; h < kHypotheses; ++h) scores_[h] = -sums[h];
}

void HasteDifferenceStar::updateScores(int /*index*/, const WindowEvent& added, const WindowEvent& evicted) {
  float* const diff = diff_.data();
  alignas(32) float xa[kPadded], ya[kPadded], xe[kPadded], ye[kPadded];
  patchCoordinates(added.x, added.y, xa, ya);
  patchCoordinates(evicted.x, evicted.y, xe, ye);
  for (int h = 0; h < kHypotheses; ++h) {
    double delta = 0;  // change of -sum(D^2), from the stored float values so it stays consistent
    int base;
    float w[4];
    if (stencil(xa[h], ya[h], base, w)) {
      for (int k = 0; k < 4; ++k) {
        float& v = diff[static_cast<std::size_t>(base + kStencilOffset[k]) * kHypotheses + h];
        const float before = v;
        v = before - w[k] * kInvWindow;
        delta += double(before) * double(before) - double(v) * double(v);
      }
    }
    if (stencil(xe[h], ye[h], base, w)) {
      for (int k = 0; k < 4; ++k) {
        float& v = diff[static_cast<std::size_t>(base + kStencilOffset[k]) * kHypotheses + h];
        const float before = v;
        v = before + w[k] * kInvWindow;
        delta += double(before) * double(before) - double(v) * double(v);
      }
    }
    scores_[h] += delta;
  }
}

// ---- HasteCorrelation* ---------------------------------------------------------------------------

HasteCorrelationStar::HasteCorrelationStar(const HasteParams& params)
    : HasteTracker(params), samples_(static_cast<std::size_t>(kWindow) * kPadded) {}

void HasteCorrelationStar::rebuildScores() {
  std::array<double, kHypotheses> sums{};
  // The window's storage order does not matter for the sums (entries [0, count_) are the window).
  for (int i = 0; i < count_; ++i) {
    const WindowEvent& e = window_[static_cast<std::size_t>(i)];
    float* v = &samples_[static_cast<std::size_t>(i) * kPadded];
    sampleHypotheses(normalized_, e.x, e.y, v);
    for (int h = 0; h < kHypotheses; ++h) sums[h] += v[h];
  }
  for (int h = 0; h < kHypotheses; ++h) scores_[h] = sums[h] * kInvWindow;
}

void HasteCorrelationStar::updateScores(int index, const WindowEvent& added, const WindowEvent& /*evicted*/) {
  // The evicted event's samples, stored when it entered the window (or at the last rebuild).
  float* const stored = &samples_[static_cast<std::size_t>(index) * kPadded];
  alignas(32) float va[kPadded];
  sampleHypotheses(normalized_, added.x, added.y, va);
  for (int h = 0; h < kHypotheses; ++h) scores_[h] += (double(va[h]) - double(stored[h])) * kInvWindow;
  std::copy(va, va + kPadded, stored);
}

std::unique_ptr<HasteTracker> makeHasteTracker(const HasteParams& params) {
  if (params.variant == HasteVariant::kCorrelationStar) return std::make_unique<HasteCorrelationStar>(params);
  return std::make_unique<HasteDifferenceStar>(params);
}

std::array<double, HasteTracker::kHypotheses> hasteScoresFromScratch(const HasteTracker& tracker) {
  std::array<double, HasteTracker::kHypotheses> out{};
  const auto& that = tracker.normalizedTemplate();
  const int n = tracker.windowSize();
  for (int h = 0; h < HasteTracker::kHypotheses; ++h) {
    const Hypothesis& hy = tracker.hypotheses()[h];
    if (tracker.params().variant == HasteVariant::kDifferenceStar) {
      // -sum (That - M_h)^2 with M_h the splat of the window at weight 1/N, in double precision.
      std::array<double, HasteTracker::kPatchCells> model{};
      for (int i = 0; i < n; ++i) {
        const auto& e = tracker.windowEvent(i);
        float xp, yp;
        HasteTracker::toPatch(hy, e.x, e.y, xp, yp);
        int base;
        float w[4];
        if (!HasteTracker::stencil(xp, yp, base, w)) continue;
        for (int k = 0; k < 4; ++k) model[base + kStencilOffset[k]] += double(w[k]) / HasteTracker::kWindow;
      }
      double sum = 0;
      for (int c = 0; c < HasteTracker::kPatchCells; ++c) sum += (that[c] - model[c]) * (that[c] - model[c]);
      out[h] = -sum;
    } else {
      double sum = 0;
      for (int i = 0; i < n; ++i) {
        const auto& e = tracker.windowEvent(i);
        float xp, yp;
        HasteTracker::toPatch(hy, e.x, e.y, xp, yp);
        sum += HasteTracker::sample(that, xp, yp);
      }
      out[h] = sum / HasteTracker::kWindow;
    }
  }
  return out;
}

}  // namespace asynevo::frontend
