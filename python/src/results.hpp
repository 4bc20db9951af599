#pragma once
// What a run hands out, kept in memory and turned into numpy arrays: knots as a trajectory (N×8: t [s],
// tx ty tz qx qy qz qw, the TUM layout of stamped_traj_estimate.txt) and velocities (N×7: t, vx vy vz,
// wx wy wz, body frame, as velocities.txt), landmarks (M×3 world points with their ids and observation
// counts), and JSON texts as Python objects.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "asynevo/backend/estimator.hpp"
#include "asynevo/core/stamped_pose.hpp"
#include "asynevo/pipeline/pipeline.hpp"

namespace asynevo::python {

/// Keeps the final knots and landmarks a pipeline hands out (called from the backend thread; read
/// after Pipeline::run returned).
class CollectingOutput final : public pipeline::PipelineOutput {
 public:
  void onFinalKnots(const std::vector<backend::Knot>& knots) override;
  void onLandmarks(const std::vector<backend::LandmarkPoint>& landmarks) override;
  std::vector<backend::Knot> knots;
  std::vector<backend::LandmarkPoint> landmarks;
};

/// N×8 float64: t [s], tx ty tz qx qy qz qw.
pybind11::array_t<double> trajectoryArray(const std::vector<backend::Knot>& knots);
pybind11::array_t<double> trajectoryArray(const StampedTrajectory& poses);
/// N×7 float64: t [s], vx vy vz wx wy wz.
pybind11::array_t<double> velocityArray(const std::vector<backend::Knot>& knots);
/// Knot times, int64 ns.
pybind11::array_t<int64_t> knotTimes(const std::vector<backend::Knot>& knots);
/// Adds "landmarks" (M×3), "landmark_ids" (int64), "landmark_observations" (int32) to `out`.
void addLandmarks(const std::vector<backend::LandmarkPoint>& landmarks, pybind11::dict& out);
/// An N×8 trajectory array (t [s] and the pose; TUM layout) as poses; ValueError naming `what` for a
/// wrong shape, non-finite values, a zero quaternion or time going backwards.
StampedTrajectory posesFromArray(const pybind11::handle& array, const char* what);
/// json.loads(text).
pybind11::object parseJson(const std::string& text);

}  // namespace asynevo::python
