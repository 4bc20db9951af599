#pragma once
// Ray geometry shared by the two initializers (src/backend/initializer.cpp,
// src/backend/multiview_initializer.cpp): bearings, parallax angles and the depth sign of a point seen
// from two cameras. Private to src/backend.

#include <cmath>

#include "asynevo/lie/so3.hpp"

namespace asynevo::backend::view_geometry {

/// The unit bearing of a normalized image point.
inline lie::Vec3 ray(double x, double y) { return lie::Vec3(x, y, 1.0).normalized(); }

inline double angleBetween(const lie::Vec3& u, const lie::Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

enum class Chirality { Front, Behind, Undetermined };

/// Where the point seen along the unit bearings `a` (camera a) and `b` (camera b) lies for the motion
/// x_b = R x_a + t: the depths along both rays of the midpoint triangulation (closest points of the two
/// rays, least squares in camera b). A point whose parallax is below `min_angle` is Undetermined (its
/// depth sign is noise) unless its rays point away from each other once rotated, which no depth can
/// explain.
inline Chirality chirality(const lie::Mat3& R, const lie::Vec3& t, const lie::Vec3& a, const lie::Vec3& b,
                           double min_angle) {
  const lie::Vec3 u = R * a;
  const double uv = u.dot(b);
  if (uv <= 0) return Chirality::Behind;
  if (angleBetween(u, b) < min_angle) return Chirality::Undetermined;
  // Minimize |lambda_a u + t - lambda_b b|^2 over the two depths (normal equations, |u| = |b| = 1).
  const double det = 1.0 - uv * uv;
  const double ut = u.dot(t), vt = b.dot(t);
  const double lambda_a = (-ut + uv * vt) / det;
  const double lambda_b = (vt - uv * ut) / det;
  return lambda_a > 0 && lambda_b > 0 ? Chirality::Front : Chirality::Behind;
}

}  // namespace asynevo::backend::view_geometry
