#include "results.hpp"

#include <fmt/format.h>

#include <cmath>

#include "asynevo/core/time.hpp"

namespace py = pybind11;

namespace asynevo::python {

void CollectingOutput::onFinalKnots(const std::vector<backend::Knot>& k) {
  knots.insert(knots.end(), k.begin(), k.end());
}

void CollectingOutput::onLandmarks(const std::vector<backend::LandmarkPoint>& l) {
  landmarks.insert(landmarks.end(), l.begin(), l.end());
}

namespace {

py::array_t<double> matrix(std::size_t rows, std::size_t cols) {
  return py::array_t<double>({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
}

}  // namespace

py::array_t<double> trajectoryArray(const std::vector<backend::Knot>& knots) {
  auto a = matrix(knots.size(), 8);
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    m(r, 0) = nsToSeconds(knots[i].t_ns);
    for (py::ssize_t c = 0; c < 7; ++c) m(r, c + 1) = knots[i].pose[static_cast<std::size_t>(c)];
  }
  return a;
}

py::array_t<double> trajectoryArray(const StampedTrajectory& poses) {
  auto a = matrix(poses.size(), 8);
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    const StampedPose& p = poses[i];
    const double row[8] = {nsToSeconds(p.t_ns), p.p_w_c.x(), p.p_w_c.y(), p.p_w_c.z(),
                           p.q_w_c.x(),         p.q_w_c.y(), p.q_w_c.z(), p.q_w_c.w()};
    for (py::ssize_t c = 0; c < 8; ++c) m(r, c) = row[c];
  }
  return a;
}

py::array_t<double> velocityArray(const std::vector<backend::Knot>& knots) {
  auto a = matrix(knots.size(), 7);
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    m(r, 0) = nsToSeconds(knots[i].t_ns);
    for (py::ssize_t c = 0; c < 6; ++c) m(r, c + 1) = knots[i].velocity[static_cast<std::size_t>(c)];
  }
  return a;
}

py::array_t<int64_t> knotTimes(const std::vector<backend::Knot>& knots) {
  py::array_t<int64_t> a(static_cast<py::ssize_t>(knots.size()));
  auto m = a.mutable_unchecked<1>();
  for (std::size_t i = 0; i < knots.size(); ++i) m(static_cast<py::ssize_t>(i)) = knots[i].t_ns;
  return a;
}

void addLandmarks(const std::vector<backend::LandmarkPoint>& landmarks, py::dict& out) {
  auto points = matrix(landmarks.size(), 3);
  py::array_t<int64_t> ids(static_cast<py::ssize_t>(landmarks.size()));
  py::array_t<int32_t> observations(static_cast<py::ssize_t>(landmarks.size()));
  auto pm = points.mutable_unchecked<2>();
  auto im = ids.mutable_unchecked<1>();
  auto om = observations.mutable_unchecked<1>();
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    for (py::ssize_t c = 0; c < 3; ++c) pm(r, c) = landmarks[i].p_w(c);
    im(r) = landmarks[i].id;
    om(r) = landmarks[i].observations;
  }
  out["landmarks"] = points;
  out["landmark_ids"] = ids;
  out["landmark_observations"] = observations;
}

StampedTrajectory posesFromArray(const py::handle& obj, const char* what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2 || a.shape(1) != 8)
    throw py::value_error(
        fmt::format("{} must be an N×8 array (t [s], tx ty tz qx qy qz qw) or a TUM file path", what));
  const auto m = a.unchecked<2>();
  StampedTrajectory poses(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    for (py::ssize_t c = 0; c < 8; ++c)
      if (!std::isfinite(m(i, c))) throw py::value_error(fmt::format("{}[{}, {}] is not finite", what, i, c));
    StampedPose& p = poses[static_cast<std::size_t>(i)];
    p.t_ns = secondsToNs(m(i, 0));
    p.p_w_c = Eigen::Vector3d(m(i, 1), m(i, 2), m(i, 3));
    Eigen::Quaterniond q(m(i, 7), m(i, 4), m(i, 5), m(i, 6));
    if (q.norm() < 1e-9) throw py::value_error(fmt::format("{}[{}] has a zero quaternion", what, i));
    p.q_w_c = q.normalized();
    if (i > 0 && p.t_ns < poses[static_cast<std::size_t>(i - 1)].t_ns)
      throw py::value_error(
          fmt::format("{} is not sorted by time: row {} is earlier than row {}", what, i, i - 1));
  }
  return poses;
}

py::object parseJson(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

}  // namespace asynevo::python
