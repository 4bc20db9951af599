#include "asynevo/core/camera/camera_model.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace asynevo {

namespace {

constexpr double kHalfPi = 1.57079632679489661923;

// Equidistant (Kannala-Brandt) polynomial theta_d(theta) = theta (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸)
// and its derivative. Kannala & Brandt, "A generic camera model and calibration method for
// conventional, wide-angle, and fish-eye lenses", TPAMI 2006; the same form as OpenCV's cv::fisheye
// and Kalibr's "equidistant" model.
struct ThetaD {
  double value;
  double derivative;
};
ThetaD equidistantThetaD(const std::vector<double>& k, double theta) {
  const double t2 = theta * theta;
  const double t4 = t2 * t2;
  const double t6 = t4 * t2;
  const double t8 = t4 * t4;
  return {theta * (1 + k[0] * t2 + k[1] * t4 + k[2] * t6 + k[3] * t8),
          1 + 3 * k[0] * t2 + 5 * k[1] * t4 + 7 * k[2] * t6 + 9 * k[3] * t8};
}

// Radtan given with four coefficients (k1 k2 p1 p2, as Kalibr writes it) means k3 = 0.
std::vector<double> completeCoefficients(DistortionModel model, const std::vector<double>& coefficients) {
  std::vector<double> out(coefficients);
  if (model == DistortionModel::kRadtan && coefficients.size() == 4) out.resize(5, 0.0);
  return out;
}

}  // namespace

const char* distortionModelName(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return "none";
    case DistortionModel::kRadtan:
      return "radtan";
    case DistortionModel::kEquidistant:
      return "equidistant";
  }
  return "unknown";
}

int CameraModel::coefficientCount(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return 0;
    case DistortionModel::kRadtan:
      return 5;
    case DistortionModel::kEquidistant:
      return 4;
  }
  return 0;
}

CameraModel::CameraModel(int width, int height, double fx, double fy, double cx, double cy,
                         DistortionModel model, const std::vector<double>& coefficients)
    : width_(width),
      height_(height),
      fx_(fx),
      fy_(fy),
      cx_(cx),
      cy_(cy),
      model_(model),
      coefficients_(completeCoefficients(model, coefficients)) {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument(fmt::format("camera size must be positive, got {}x{}", width, height));
  }
  for (double value : {fx, fy, cx, cy}) {
    if (!std::isfinite(value)) throw std::invalid_argument("camera intrinsics must be finite");
  }
  if (fx <= 0 || fy <= 0) {
    throw std::invalid_argument(fmt::format("focal lengths must be positive, got fx={} fy={}", fx, fy));
  }
  const auto expected = static_cast<std::size_t>(coefficientCount(model));
  if (coefficients_.size() != expected) {
    throw std::invalid_argument(fmt::format("the {} model takes {} distortion coefficients, got {}",
                                            distortionModelName(model), expected, coefficients.size()));
  }
  for (double value : coefficients_) {
    if (!std::isfinite(value)) throw std::invalid_argument("distortion coefficients must be finite");
  }
}

CameraModel CameraModel::davis240cEcd() {
  // Event Camera Dataset (Mueggler et al., IJRR 2017), calib.txt of the DAVIS240C sequences.
  return CameraModel(240, 180, 199.092366542, 198.82882047, 132.192071378, 110.712660011,
                     DistortionModel::kRadtan,
                     {-0.368436311798, 0.150947243557, -0.000296130534385, -0.000759431726241, 0.0});
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& xn) const {
  const double x = xn.x();
  const double y = xn.y();
  switch (model_) {
    case DistortionModel::kNone:
      return xn;
    case DistortionModel::kRadtan: {
      // Brown-Conrady radial-tangential model as used by OpenCV (calib3d "Detailed description")
      // and Kalibr "radtan":
      //   xd = x (1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2 x²)
      //   yd = y (1 + k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2 y²) + 2 p2 x y
      const double k1 = coefficients_[0], k2 = coefficients_[1], p1 = coefficients_[2], p2 = coefficients_[3],
                   k3 = coefficients_[4];
      const double r2 = x * x + y * y;
      const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
      return {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
              y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
    }
    case DistortionModel::kEquidistant: {
      // theta = atan(r), xd = theta_d(theta) / r * x (Kannala-Brandt; OpenCV fisheye::distortPoints).
      const double r = std::hypot(x, y);
      if (r < 1e-12) return xn;
      const double theta_d = equidistantThetaD(coefficients_, std::atan(r)).value;
      return xn * (theta_d / r);
    }
  }
  return xn;
}

Eigen::Matrix2d CameraModel::distortJacobian(const Eigen::Vector2d& xn) const {
  const double x = xn.x();
  const double y = xn.y();
  Eigen::Matrix2d J = Eigen::Matrix2d::Identity();
  switch (model_) {
    case DistortionModel::kNone:
      break;
    case DistortionModel::kRadtan: {
      const double k1 = coefficients_[0], k2 = coefficients_[1], p1 = coefficients_[2], p2 = coefficients_[3],
                   k3 = coefficients_[4];
      const double r2 = x * x + y * y;
      const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
      const double d_radial_d_r2 = k1 + r2 * (2 * k2 + 3 * r2 * k3);  // d radial / d(r²)
      // d radial/dx = 2 x d_radial_d_r2
      J(0, 0) = radial + 2 * x * x * d_radial_d_r2 + 2 * p1 * y + 6 * p2 * x;
      J(0, 1) = 2 * x * y * d_radial_d_r2 + 2 * p1 * x + 2 * p2 * y;
      J(1, 0) = 2 * x * y * d_radial_d_r2 + 2 * p1 * x + 2 * p2 * y;
      J(1, 1) = radial + 2 * y * y * d_radial_d_r2 + 6 * p1 * y + 2 * p2 * x;
      break;
    }
    case DistortionModel::kEquidistant: {
      const double r = std::hypot(x, y);
      if (r < 1e-8) break;  // s = 1 + O(r²), ds/dr / r = O(1): J = I + O(r²)
      const double theta = std::atan(r);
      const ThetaD td = equidistantThetaD(coefficients_, theta);
      const double s = td.value / r;
      // ds/dr = (theta_d'(θ) θ'(r) r - theta_d) / r², θ'(r) = 1 / (1 + r²)
      const double ds_dr = (td.derivative / (1 + r * r) * r - td.value) / (r * r);
      J = s * Eigen::Matrix2d::Identity() + (ds_dr / r) * (xn * xn.transpose());
      break;
    }
  }
  return J;
}

UndistortResult CameraModel::undistort(const Eigen::Vector2d& xd, const UndistortOptions& options) const {
  UndistortResult result;
  if (!xd.allFinite()) return result;
  switch (model_) {
    case DistortionModel::kNone:
      result.xn = xd;
      result.converged = true;
      return result;
    case DistortionModel::kRadtan: {
      // Newton's method on distort(x) = xd from x = xd, with step halving when the residual grows.
      // The solution is accepted only where the model is locally invertible (det J > 0), i.e. on the
      // branch that contains the principal point; beyond the fold of a strong radial distortion the
      // inverse is not unique and we report failure rather than return an arbitrary root.
      Eigen::Vector2d x = xd;
      Eigen::Vector2d residual = distort(x) - xd;
      double norm = residual.norm();
      for (int it = 0; it < options.max_iterations; ++it) {
        if (norm <= options.tolerance) break;
        const Eigen::Matrix2d J = distortJacobian(x);
        const double det = J.determinant();
        if (!(det > 0)) break;
        Eigen::Vector2d step = J.inverse() * residual;
        bool improved = false;
        for (int halving = 0; halving < 30; ++halving) {
          const Eigen::Vector2d candidate = x - step;
          const Eigen::Vector2d candidate_residual = distort(candidate) - xd;
          const double candidate_norm = candidate_residual.norm();
          if (candidate_norm < norm) {
            x = candidate;
            residual = candidate_residual;
            norm = candidate_norm;
            improved = true;
            break;
          }
          step *= 0.5;
        }
        result.iterations = it + 1;
        if (!improved) break;
      }
      result.xn = x;
      result.residual = norm;
      result.converged =
          std::isfinite(norm) && norm <= options.tolerance && distortJacobian(x).determinant() > 0;
      return result;
    }
    case DistortionModel::kEquidistant: {
      // Solve theta_d(θ) = |xd| for θ in [0, π/2) by Newton's method (the inverse used by
      // OpenCV fisheye::undistortPoints), then xn = tan(θ) / |xd| * xd.
      const double theta_d = xd.norm();
      if (theta_d < 1e-15) {
        result.xn = xd;
        result.converged = true;
        return result;
      }
      double theta = std::min(theta_d, kHalfPi - 1e-6);
      double f = equidistantThetaD(coefficients_, theta).value - theta_d;
      for (int it = 0; it < options.max_iterations; ++it) {
        if (std::fabs(f) <= options.tolerance) break;
        const ThetaD td = equidistantThetaD(coefficients_, theta);
        if (!(td.derivative > 0)) break;
        theta -= f / td.derivative;
        if (!(theta >= 0 && theta < kHalfPi)) break;
        f = equidistantThetaD(coefficients_, theta).value - theta_d;
        result.iterations = it + 1;
      }
      const bool in_domain = theta >= 0 && theta < kHalfPi;
      const bool monotonic = in_domain && equidistantThetaD(coefficients_, theta).derivative > 0;
      result.residual = std::fabs(f);
      result.xn = in_domain ? Eigen::Vector2d(xd * (std::tan(theta) / theta_d)) : xd;
      result.converged = in_domain && monotonic && std::fabs(f) <= options.tolerance;
      return result;
    }
  }
  return result;
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& p_c, double min_depth) const {
  if (!(p_c.z() > min_depth) || !p_c.allFinite()) return std::nullopt;
  return normalizedToPixel(Eigen::Vector2d(p_c.x() / p_c.z(), p_c.y() / p_c.z()));
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& p_c,
                                                    Eigen::Matrix<double, 2, 3>* J_pixel_p,
                                                    double min_depth) const {
  if (!(p_c.z() > min_depth) || !p_c.allFinite()) return std::nullopt;
  const double inv_z = 1.0 / p_c.z();
  const Eigen::Vector2d xn(p_c.x() * inv_z, p_c.y() * inv_z);
  if (J_pixel_p) {
    Eigen::Matrix<double, 2, 3> d_xn_d_p;
    d_xn_d_p << inv_z, 0, -xn.x() * inv_z, 0, inv_z, -xn.y() * inv_z;
    const Eigen::Matrix2d d_pixel_d_xd = Eigen::Vector2d(fx_, fy_).asDiagonal();
    *J_pixel_p = d_pixel_d_xd * distortJacobian(xn) * d_xn_d_p;
  }
  return normalizedToPixel(xn);
}

std::optional<Eigen::Vector2d> CameraModel::unproject(const Eigen::Vector2d& pixel,
                                                      const UndistortOptions& options) const {
  const UndistortResult r = undistort(pixelToDistorted(pixel), options);
  if (!r.converged) return std::nullopt;
  return r.xn;
}

std::optional<Eigen::Vector3d> CameraModel::unprojectBearing(const Eigen::Vector2d& pixel,
                                                             const UndistortOptions& options) const {
  const auto xn = unproject(pixel, options);
  if (!xn) return std::nullopt;
  return Eigen::Vector3d(xn->x(), xn->y(), 1.0).normalized();
}

template <typename Scalar>
UndistortionTable<Scalar> CameraModel::undistortionTable(const UndistortOptions& options) const {
  UndistortionTable<Scalar> table(width_, height_);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const UndistortResult r = undistort(pixelToDistorted(Eigen::Vector2d(x, y)), options);
      table.set(x, y, static_cast<Scalar>(r.xn.x()), static_cast<Scalar>(r.xn.y()), r.converged);
    }
  }
  return table;
}

template UndistortionTable<float> CameraModel::undistortionTable<float>(const UndistortOptions&) const;
template UndistortionTable<double> CameraModel::undistortionTable<double>(const UndistortOptions&) const;

std::string CameraModel::summary() const {
  std::string s = fmt::format("{}x{} fx={:.6g} fy={:.6g} cx={:.6g} cy={:.6g} {}", width_, height_, fx_, fy_,
                              cx_, cy_, distortionModelName(model_));
  if (!coefficients_.empty()) s += fmt::format(" [{:.6g}]", fmt::join(coefficients_, " "));
  return s;
}

}  // namespace asynevo
