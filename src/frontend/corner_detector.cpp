// Arc* and FA-Harris as described in shared/reference/frontend.md §3-§5 (facts and parameters from
// Alzugaray & Chli, RA-L 2018; Mueggler et al., BMVC 2017; Li et al., IROS 2019). Our own code.
#include "asynevo/frontend/corner_detector.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace asynevo::frontend {

const ArcCircle& smallArcCircle() {
  static const ArcCircle c{16,
                           3,
                           6,
                           {{{0, 3},
                             {1, 3},
                             {2, 2},
                             {3, 1},
                             {3, 0},
                             {3, -1},
                             {2, -2},
                             {1, -3},
                             {0, -3},
                             {-1, -3},
                             {-2, -2},
                             {-3, -1},
                             {-3, 0},
                             {-3, 1},
                             {-2, 2},
                             {-1, 3}}}};
  return c;
}

const ArcCircle& largeArcCircle() {
  static const ArcCircle c{20, 4, 8, {{{0, 4},   {1, 4},  {2, 3},  {3, 2},  {4, 1},   {4, 0},   {4, -1},
                                       {3, -2},  {2, -3}, {1, -4}, {0, -4}, {-1, -4}, {-2, -3}, {-3, -2},
                                       {-4, -1}, {-4, 0}, {-4, 1}, {-3, 2}, {-2, 3},  {-1, 4}}}};
  return c;
}

int arcStarLength(const int64_t* ring, int n, int lmin) {
  assert(n >= 3 && lmin >= 1 && lmin <= n);
  int newest = 0;
  for (int k = 1; k < n; ++k)
    if (ring[k] > ring[newest]) newest = k;  // first maximum in index order
  int64_t segment_min = ring[newest];
  int right = newest + 1 == n ? 0 : newest + 1;  // clockwise frontier
  int left = newest == 0 ? n - 1 : newest - 1;   // counter-clockwise frontier
  int64_t right_min = ring[right];
  int64_t left_min = ring[left];
  auto advance = [&](bool take_right) {
    if (take_right) {
      right = right + 1 == n ? 0 : right + 1;
      right_min = std::min(right_min, ring[right]);
    } else {
      left = left == 0 ? n - 1 : left - 1;
      left_min = std::min(left_min, ring[left]);
    }
  };
  // Forced growth up to lmin elements.
  for (int i = 1; i < lmin; ++i) {
    const bool take_right = ring[right] > ring[left];
    segment_min = std::min(segment_min, take_right ? right_min : left_min);
    advance(take_right);
  }
  // Conditional growth: the arc grows while the newer frontier candidate is not older than it.
  int length = lmin;
  for (int i = lmin; i < n; ++i) {
    const bool take_right = ring[right] > ring[left];
    const int64_t candidate = take_right ? ring[right] : ring[left];
    if (candidate >= segment_min) {
      length = i + 1;
      segment_min = std::min(segment_min, take_right ? right_min : left_min);
    }
    advance(take_right);
  }
  return length;
}

double harrisScore(const BinaryPatch& patch, double k) {
  // Separable integer kernel K(a, b) = S[a] D[b] (the /12 is applied at the end).
  static constexpr int kS[5] = {1, 4, 6, 4, 1};
  static constexpr int kD[5] = {1, 2, 0, -2, -1};
  // patch index [j][i]: j = dy + 4 (second index of the reference's P(i, j)), i = dx + 4.
  // First pass along i: smoothed (S) and differentiated (D) rows, 5 outputs per row of 9.
  int ps[kHarrisSize][5];
  int pd[kHarrisSize][5];
  for (int j = 0; j < kHarrisSize; ++j) {
    for (int u = 0; u < 5; ++u) {
      int s = 0, d = 0;
      for (int a = 0; a < 5; ++a) {
        const int v = patch[j * kHarrisSize + u + a];
        s += kS[a] * v;
        d += kD[a] * v;
      }
      ps[j][u] = s;
      pd[j][u] = d;
    }
  }
  // Gaussian window sigma 1 on the 5x5 valid area, normalised to sum 1.
  static const auto kWindow = [] {
    std::array<double, 25> h{};
    double sum = 0;
    for (int v = 0; v < 5; ++v)
      for (int u = 0; u < 5; ++u)
        sum += h[v * 5 + u] = std::exp(-((u - 2) * (u - 2) + (v - 2) * (v - 2)) / 2.0);
    for (double& x : h) x /= sum;
    return h;
  }();
  double a_sum = 0, b_sum = 0, c_sum = 0;
  for (int v = 0; v < 5; ++v) {
    for (int u = 0; u < 5; ++u) {
      int g1 = 0, g2 = 0;  // G1: S along i, D along j; G2: D along i, S along j
      for (int b = 0; b < 5; ++b) {
        g1 += kD[b] * ps[v + b][u];
        g2 += kS[b] * pd[v + b][u];
      }
      const double x1 = g1 / 12.0, x2 = g2 / 12.0, w = kWindow[v * 5 + u];
      a_sum += w * x1 * x1;
      b_sum += w * x1 * x2;
      c_sum += w * x2 * x2;
    }
  }
  return a_sum * c_sum - b_sum * b_sum - k * (a_sum + c_sum) * (a_sum + c_sum);
}

CornerDetector::CornerDetector(const SurfaceOfActiveEvents& sae, const DetectorParams& params)
    : sae_(sae), params_(params), width_(sae.width()), height_(sae.height()) {
  assert(params.harris_latest >= 1 && params.harris_latest <= kHarrisSize * kHarrisSize);
  const auto& s = smallArcCircle();
  for (int i = 0; i < s.n; ++i) small_offsets_[i] = s.offsets[i][1] * width_ + s.offsets[i][0];
  const auto& l = largeArcCircle();
  for (int i = 0; i < l.n; ++i) large_offsets_[i] = l.offsets[i][1] * width_ + l.offsets[i][0];
}

int CornerDetector::arcLength(const ArcCircle& c, const int* offsets, int p, int x, int y) const {
  assert(!inBorder(x, y));
  const int64_t* centre = sae_.sae(p) + sae_.index(x, y);
  int64_t ring[20];
  for (int i = 0; i < c.n; ++i) ring[i] = centre[offsets[i]];
  return arcStarLength(ring, c.n, c.lmin);
}

bool CornerDetector::isArcCandidate(int p, int x, int y) const {
  const ArcCircle& s = smallArcCircle();
  if (!arcLengthPasses(arcLength(s, small_offsets_.data(), p, x, y), s)) return false;
  const ArcCircle& l = largeArcCircle();
  return arcLengthPasses(arcLength(l, large_offsets_.data(), p, x, y), l);
}

bool CornerDetector::buildPatch(int p, int x, int y, BinaryPatch& patch) const {
  assert(!inBorder(x, y));
  // Collect fired pixels of the window, then keep the `latest` newest (partial selection).
  std::array<int64_t, kHarrisSize * kHarrisSize> times;
  std::array<uint8_t, kHarrisSize * kHarrisSize> cells;
  int count = 0;
  const int64_t* map = sae_.sae(p);
  for (int j = 0; j < kHarrisSize; ++j) {
    const int64_t* row = map + sae_.index(x - kHarrisHalf, y - kHarrisHalf + j);
    for (int i = 0; i < kHarrisSize; ++i) {
      if (row[i] != kNever) {
        times[count] = row[i];
        cells[count] = static_cast<uint8_t>(j * kHarrisSize + i);
        ++count;
      }
    }
  }
  const int latest = params_.harris_latest;
  if (count < latest) return false;
  patch.fill(0);
  if (count == latest) {
    for (int i = 0; i < count; ++i) patch[cells[i]] = 1;
    return true;
  }
  // Threshold = latest-th newest time; take all strictly newer, then ties in scan order.
  std::array<int64_t, kHarrisSize * kHarrisSize> sorted;
  std::copy(times.begin(), times.begin() + count, sorted.begin());
  std::nth_element(sorted.begin(), sorted.begin() + (latest - 1), sorted.begin() + count, std::greater<>());
  const int64_t threshold = sorted[latest - 1];
  int taken = 0;
  for (int i = 0; i < count; ++i)
    if (times[i] > threshold) {
      patch[cells[i]] = 1;
      ++taken;
    }
  for (int i = 0; i < count && taken < latest; ++i)
    if (times[i] == threshold) {
      patch[cells[i]] = 1;
      ++taken;
    }
  return true;
}

double CornerDetector::harrisAt(int p, int x, int y) const {
  BinaryPatch patch;
  if (!buildPatch(p, x, y, patch)) return -std::numeric_limits<double>::infinity();
  return harrisScore(patch, params_.harris_k);
}

CornerResult CornerDetector::detect(const Event& e, bool accepted) const {
  CornerResult r;
  r.accepted = accepted;
  if (!accepted || inBorder(e.x, e.y)) return r;
  const int p = polarityIndex(e);
  r.candidate = isArcCandidate(p, e.x, e.y);
  if (!r.candidate) return r;
  if (params_.kind == DetectorKind::kArcStar) {
    r.corner = true;
    return r;
  }
  const double score = harrisAt(p, e.x, e.y);
  r.score = std::isfinite(score) ? static_cast<float>(score) : 0.f;
  r.corner = score > params_.harris_threshold;
  return r;
}

}  // namespace asynevo::frontend
