#pragma once
// Surface of Active Events (SAE) with the refractory ("redundant spike") filter of Arc* and
// FA-Harris (Alzugaray & Chli, RA-L 2018; Li et al., IROS 2019; shared/reference/frontend.md §2).
//
// Per polarity p two W x H maps of int64 ns timestamps (pixel index y * W + x):
//  - latestAt(p, x, y): time of the latest event of polarity p at the pixel, whether filtered or not
//    (both polarities of a pixel stored side by side: the filter reads both, one cache line per event);
//  - sae(p): time of the latest event of polarity p that passed the filter (FA-Harris' "G-SAE"),
//    row-major per polarity (the detectors read its neighbourhoods).
// An event (t, x, y, p) passes iff t > latest_p + dt_f or latest_q > latest_p (q = other polarity:
// the pixel flipped polarity since). Both maps start at kNever, a sentinel far below any event time,
// so time may start at 0 (the references initialise with 0 and then drop the first 50 ms).

#include <cstdint>
#include <limits>
#include <vector>

#include "asynevo/core/event.hpp"

namespace asynevo::frontend {

/// Starts loading the cache line holding `address` (a hint; no effect on any value). On x86 the
/// instruction is written out: GCC 12 at -O3 dropped __builtin_prefetch (and _mm_prefetch) of these
/// map entries from the generated code.
inline void prefetchLine(const void* address) {
#if defined(__x86_64__) || defined(__i386__)
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(address)));
#else
  __builtin_prefetch(address);
#endif
}

/// "Never fired": far below any timestamp, and far enough above INT64_MIN that t - kNever and
/// kNever + dt do not overflow for realistic times.
constexpr int64_t kNever = std::numeric_limits<int64_t>::min() / 4;

class SurfaceOfActiveEvents {
 public:
  SurfaceOfActiveEvents(int width, int height, int64_t refractory_ns);

  /// Updates the maps for `e` (always the latest map; the SAE only when the filter accepts) and
  /// returns whether the filter accepted it. The caller guarantees x < width, y < height.
  bool update(const Event& e) {
    const int p = polarityIndex(e);
    const std::size_t i = index(e.x, e.y);
    int64_t* latest = &latest_[2 * i];
    int64_t& latest_p = latest[p];
    const bool accept = e.t_ns > latest_p + refractory_ns_ || latest[1 - p] > latest_p;
    latest_p = e.t_ns;
    if (accept) sae_[p][i] = e.t_ns;
    return accept;
  }

  /// Hint: an event of polarity channel p at pixel index i is updated soon; starts loading the map
  /// entries update() touches into the cache (the maps are larger than the caches and events arrive
  /// at random pixels). No effect on any value.
  void prefetch(std::size_t i, int p) const {
    prefetchLine(&latest_[2 * i]);
    prefetchLine(&sae_[p][i]);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int64_t refractoryNs() const { return refractory_ns_; }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }
  /// Filtered SAE of polarity channel p (0 = OFF, 1 = ON), row-major.
  const int64_t* sae(int p) const { return sae_[p].data(); }
  int64_t saeAt(int p, int x, int y) const { return sae_[p][index(x, y)]; }
  int64_t latestAt(int p, int x, int y) const { return latest_[2 * index(x, y) + p]; }
  void clear();

 private:
  int width_;
  int height_;
  int64_t refractory_ns_;
  std::vector<int64_t> sae_[2];
  std::vector<int64_t> latest_;  ///< [pixel][polarity]
};

}  // namespace asynevo::frontend
