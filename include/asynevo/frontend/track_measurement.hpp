#pragma once
// What the frontend hands to the backend: one feature position at one time.

#include <cstdint>

namespace asynevo {

/// A feature measurement. Ids are 64-bit, increasing, never reused (DESIGN.md §3); the times of one
/// feature never decrease, but measurements of different features are not globally time-ordered
/// (a tracker's state time is the time of the middle event of its window, which lags the newest event).
struct TrackMeasurement {
  int64_t feature_id = 0;
  int64_t t_ns = 0;
  float x = 0.f;   ///< raw (distorted) pixel column, (0,0) = centre of the top-left pixel
  float y = 0.f;   ///< raw pixel row
  float xn = 0.f;  ///< normalized undistorted coordinate X/Z
  float yn = 0.f;  ///< normalized undistorted coordinate Y/Z
};

}  // namespace asynevo
