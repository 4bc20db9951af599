#pragma once
// Event corner detectors on the filtered SAE: Arc* (Alzugaray & Chli, RA-L 2018) and FA-Harris
// (Li et al., IROS 2019) = refractory filter -> Arc* candidate -> Harris score of the binary 9x9
// patch of the newest same-polarity SAE pixels. Every stage is callable on its own
// (shared/reference/frontend.md §3, §4.3, §5). Nothing here allocates per event.

#include <array>
#include <cstdint>

#include "asynevo/core/event.hpp"
#include "asynevo/frontend/sae.hpp"

namespace asynevo::frontend {

// ---- Arc* -------------------------------------------------------------------------------------

/// A Bresenham circle: offsets (dx, dy) in clockwise order starting at (0, +r), and the Arc*
/// bounds [lmin, lmax] of the newest arc (its complement [n - lmax, n - lmin] also passes).
struct ArcCircle {
  int n;
  int lmin;
  int lmax;
  std::array<std::array<int, 2>, 20> offsets;
};
/// r = 3, 16 pixels, bounds [3, 6] (+ [10, 13]).
const ArcCircle& smallArcCircle();
/// r = 4, 20 pixels, bounds [4, 8] (+ [12, 16]).
const ArcCircle& largeArcCircle();

/// Arc* length of the newest arc of a ring of n timestamps (Alzugaray & Chli 2018, as documented in
/// reference §3.1: grows from the newest element towards the newer neighbour; counts the elements
/// processed until the arc last grew). Always in [lmin, n].
int arcStarLength(const int64_t* ring, int n, int lmin);
/// Whether an arc length passes the test of a circle: L <= lmax or n - lmax <= L <= n - lmin.
inline bool arcLengthPasses(int length, const ArcCircle& c) {
  return length <= c.lmax || (length >= c.n - c.lmax && length <= c.n - c.lmin);
}

// ---- Harris score of a binary patch -----------------------------------------------------------

constexpr int kHarrisHalf = 4;                                       ///< window half size w
constexpr int kHarrisSize = 2 * kHarrisHalf + 1;                     ///< 9
using BinaryPatch = std::array<uint8_t, kHarrisSize * kHarrisSize>;  ///< [dy + 4][dx + 4]

/// Harris score of a binary 9x9 patch as in eHarris/FA-Harris (reference §4.3): 5x5 Sobel-like
/// kernel S = (1,4,6,4,1) x D = (1,2,0,-2,-1) / 12, valid 5x5 gradients, Gaussian sigma 1 window
/// normalised to sum 1, R = A C - B^2 - k (A + C)^2.
double harrisScore(const BinaryPatch& patch, double k = 0.04);

// ---- the detector -----------------------------------------------------------------------------

enum class DetectorKind { kFaHarris, kArcStar };

struct DetectorParams {
  DetectorKind kind = DetectorKind::kFaHarris;
  double harris_threshold = 8.0;
  double harris_k = 0.04;
  int harris_latest = 25;
};

/// What the stages said about one event.
struct CornerResult {
  bool accepted = false;   ///< passed the refractory filter
  bool candidate = false;  ///< passed the Arc* test (both circles)
  bool corner = false;     ///< final decision
  float score = 0.f;       ///< Harris score (FA-Harris; 0 when not computed)
};

class CornerDetector {
 public:
  /// The detector reads (never writes) `sae`, which must outlive it.
  CornerDetector(const SurfaceOfActiveEvents& sae, const DetectorParams& params);

  /// Full pipeline for an event whose maps were already updated by sae.update(e) (that call's
  /// result is `accepted`).
  CornerResult detect(const Event& e, bool accepted) const;

  /// Stage: in the 4-px border band (no circle or window fits).
  bool inBorder(int x, int y) const {
    return x < kHarrisHalf || y < kHarrisHalf || x >= width_ - kHarrisHalf || y >= height_ - kHarrisHalf;
  }
  /// Stage: Arc* test of both circles on SAE channel p at (x, y) (must not be inBorder).
  bool isArcCandidate(int p, int x, int y) const;
  /// Arc* length on one circle at (x, y).
  int arcLength(const ArcCircle& c, const int* offsets, int p, int x, int y) const;
  /// Stage: build the binary patch of the `latest` newest fired pixels of the 9x9 window of SAE
  /// channel p around (x, y) (must not be inBorder). False when fewer pixels have fired.
  bool buildPatch(int p, int x, int y, BinaryPatch& patch) const;
  /// Stage: Harris score at (x, y) (buildPatch + harrisScore); NaN-free, -inf if no patch.
  double harrisAt(int p, int x, int y) const;

  const DetectorParams& params() const { return params_; }
  /// The FA-Harris threshold from now on (adaptive detection).
  void setHarrisThreshold(double threshold) { params_.harris_threshold = threshold; }

 private:
  const SurfaceOfActiveEvents& sae_;
  DetectorParams params_;
  int width_;
  int height_;
  std::array<int, 16> small_offsets_{};  ///< linear index offsets of the small circle
  std::array<int, 20> large_offsets_{};
};

}  // namespace asynevo::frontend
