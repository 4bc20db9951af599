// Joint robust fit of one rotation model to all feature tracks (see rotation_check.hpp).
#include "asynevo/frontend/rotation_check.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace asynevo::frontend {

namespace {

struct Track {
  std::vector<const TrackMeasurement*> m;
  double t0 = 0;  ///< seconds relative to t_ref of its first measurement
};

Eigen::Matrix3d expSo3(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const std::size_t k =
      std::min(v.size() - 1, static_cast<std::size_t>(std::floor(q * (v.size() - 1) + 0.5)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

RotationFitResult fitCommonRotation(const std::vector<TrackMeasurement>& measurements, double fx, double fy,
                                    const RotationFitOptions& options) {
  RotationFitResult result;
  std::map<int64_t, Track> by_id;
  int64_t t_min = INT64_MAX, t_max = INT64_MIN;
  for (const TrackMeasurement& m : measurements) {
    by_id[m.feature_id].m.push_back(&m);
    t_min = std::min(t_min, m.t_ns);
    t_max = std::max(t_max, m.t_ns);
  }
  std::vector<Track> tracks;
  for (auto& [id, track] : by_id) {
    if (static_cast<int>(track.m.size()) < options.min_measurements) {
      ++result.tracks_excluded;
      continue;
    }
    std::sort(track.m.begin(), track.m.end(),
              [](const TrackMeasurement* a, const TrackMeasurement* b) { return a->t_ns < b->t_ns; });
    tracks.push_back(std::move(track));
  }
  if (tracks.size() < 2)
    throw std::invalid_argument(
        "fitCommonRotation: fewer than 2 tracks with enough measurements (the rotation is not determined)");
  result.t_ref_ns = t_min + (t_max - t_min) / 2;
  auto seconds = [&](int64_t t) { return static_cast<double>(t - result.t_ref_ns) * 1e-9; };
  for (Track& tr : tracks) tr.t0 = seconds(tr.m.front()->t_ns);

  const int n_global = options.with_acceleration ? 6 : 3;
  const int n_tracks = static_cast<int>(tracks.size());
  const int n = n_global + 2 * n_tracks;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < n_tracks; ++j) {
    x(n_global + 2 * j) = tracks[j].m.front()->xn;
    x(n_global + 2 * j + 1) = tracks[j].m.front()->yn;
  }
  // Residual (pixels) of one measurement given the global parameters g and the track's bearing b.
  auto residual = [&](const Eigen::VectorXd& g, double u, double v, double t0, double t, double xn,
                      double yn) {
    const Eigen::Vector3d w = g.head<3>();
    Eigen::Vector3d a = Eigen::Vector3d::Zero();
    if (n_global == 6) a = g.segment<3>(3);
    const Eigen::Matrix3d r_t = expSo3(w * t + 0.5 * a * t * t);
    const Eigen::Matrix3d r_0 = expSo3(w * t0 + 0.5 * a * t0 * t0);
    const Eigen::Vector3d p = r_t.transpose() * r_0 * Eigen::Vector3d(u, v, 1.0);
    return Eigen::Vector2d(fx * (p.x() / p.z() - xn), fy * (p.y() / p.z() - yn));
  };

  const double huber = options.huber_px;
  for (int it = 0; it < options.iterations; ++it) {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    const Eigen::VectorXd g = x.head(n_global);
    for (int j = 0; j < n_tracks; ++j) {
      const int o = n_global + 2 * j;
      for (const TrackMeasurement* m : tracks[j].m) {
        const double t = seconds(m->t_ns);
        const Eigen::Vector2d r0 = residual(g, x(o), x(o + 1), tracks[j].t0, t, m->xn, m->yn);
        // Numeric Jacobian (central differences) w.r.t. the global parameters and the track's bearing.
        Eigen::Matrix<double, 2, Eigen::Dynamic> jg(2, n_global);
        for (int k = 0; k < n_global; ++k) {
          const double step = 1e-6;
          Eigen::VectorXd gp = g, gm = g;
          gp(k) += step;
          gm(k) -= step;
          jg.col(k) = (residual(gp, x(o), x(o + 1), tracks[j].t0, t, m->xn, m->yn) -
                       residual(gm, x(o), x(o + 1), tracks[j].t0, t, m->xn, m->yn)) /
                      (2 * step);
        }
        Eigen::Matrix2d jb;
        for (int k = 0; k < 2; ++k) {
          const double step = 1e-7;
          const double du = k == 0 ? step : 0, dv = k == 1 ? step : 0;
          jb.col(k) = (residual(g, x(o) + du, x(o + 1) + dv, tracks[j].t0, t, m->xn, m->yn) -
                       residual(g, x(o) - du, x(o + 1) - dv, tracks[j].t0, t, m->xn, m->yn)) /
                      (2 * step);
        }
        const double norm = r0.norm();
        const double w = norm <= huber ? 1.0 : huber / norm;
        h.topLeftCorner(n_global, n_global) += w * jg.transpose() * jg;
        h.block(0, o, n_global, 2) += w * jg.transpose() * jb;
        h.block(o, 0, 2, n_global) += w * jb.transpose() * jg;
        h.block<2, 2>(o, o) += w * jb.transpose() * jb;
        b.head(n_global) -= w * jg.transpose() * r0;
        b.segment<2>(o) -= w * jb.transpose() * r0;
      }
    }
    h.diagonal().array() += 1e-9 * (1.0 + h.diagonal().array());
    const Eigen::VectorXd dx = h.ldlt().solve(b);
    if (!dx.allFinite()) break;
    x += dx;
    result.iterations = it + 1;
    if (dx.head(n_global).norm() < 1e-9 && dx.tail(n - n_global).norm() < 1e-10) break;
  }

  result.omega = x.head<3>();
  if (n_global == 6) result.alpha = x.segment<3>(3);
  std::vector<double> lifetimes;
  double sq = 0;
  for (int j = 0; j < n_tracks; ++j) {
    const int o = n_global + 2 * j;
    for (const TrackMeasurement* m : tracks[j].m) {
      const double r =
          residual(x.head(n_global), x(o), x(o + 1), tracks[j].t0, seconds(m->t_ns), m->xn, m->yn).norm();
      result.residuals_px.push_back(r);
      sq += r * r;
    }
    lifetimes.push_back(static_cast<double>(tracks[j].m.back()->t_ns - tracks[j].m.front()->t_ns) * 1e-9);
  }
  result.tracks_used = n_tracks;
  result.measurements = static_cast<int>(result.residuals_px.size());
  result.median_px = quantile(result.residuals_px, 0.5);
  result.p90_px = quantile(result.residuals_px, 0.9);
  result.rms_px = std::sqrt(sq / std::max<std::size_t>(1, result.residuals_px.size()));
  result.share_above_3px =
      static_cast<double>(std::count_if(result.residuals_px.begin(), result.residuals_px.end(),
                                        [](double r) { return r > 3.0; })) /
      std::max<std::size_t>(1, result.residuals_px.size());
  result.lifetime_median_s = quantile(lifetimes, 0.5);
  double sum = 0;
  for (double l : lifetimes) sum += l;
  result.lifetime_mean_s = sum / lifetimes.size();
  result.lifetime_max_s = *std::max_element(lifetimes.begin(), lifetimes.end());
  return result;
}

}  // namespace asynevo::frontend
