// asynevo.evaluate: the evaluator of 'asynevo eval' (eval::evaluate, rpg_trajectory_evaluation's
// definitions) on files or N×8 arrays, returning eval.json as a dict.

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "arguments.hpp"
#include "asynevo/core/time.hpp"
#include "asynevo/eval/evaluate.hpp"
#include "asynevo/eval/report.hpp"
#include "asynevo/io/trajectory_io.hpp"
#include "bindings.hpp"
#include "results.hpp"

namespace py = pybind11;

namespace asynevo::python {

namespace {

StampedTrajectory trajectoryArg(const py::handle& obj, const char* what) {
  return isPath(obj) ? readTumTrajectory(pathArg(obj, what)) : posesFromArray(obj, what);
}

std::vector<StampedTwist> twistsFromArray(const py::handle& obj) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2 || a.shape(1) != 7)
    throw py::value_error(
        "velocities must be an N×7 array (t [s], vx vy vz wx wy wz) or a velocities.txt path");
  const auto m = a.unchecked<2>();
  std::vector<StampedTwist> twists(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    StampedTwist& w = twists[static_cast<std::size_t>(i)];
    w.t_ns = secondsToNs(m(i, 0));
    w.v_c = Eigen::Vector3d(m(i, 1), m(i, 2), m(i, 3));
    w.w_c = Eigen::Vector3d(m(i, 4), m(i, 5), m(i, 6));
  }
  return twists;
}

py::dict evaluate(const py::object& gt_obj, const py::object& est_obj, const std::string& align,
                  const py::object& velocities, int align_frames, const std::vector<double>& rel_lengths,
                  double max_time_diff_s) {
  eval::EvalOptions options;
  const std::optional<eval::AlignType> type = eval::parseAlignType(align);
  if (!type) throw py::value_error(fmt::format("align '{}' is not sim3, se3, posyaw or none", align));
  options.align = *type;
  options.align_frames = align_frames;
  options.rel_lengths_m = rel_lengths;
  if (!(max_time_diff_s > 0)) throw py::value_error("max_time_diff_s must be positive");
  options.max_time_diff_ns = secondsToNs(max_time_diff_s);

  eval::ReportInputs inputs{isPath(gt_obj) ? pathArg(gt_obj, "gt") : "<array>",
                            isPath(est_obj) ? pathArg(est_obj, "est") : "<array>", nullptr};
  eval::EvalResult r;
  if (isPath(gt_obj) && isPath(est_obj) && (velocities.is_none() || isPath(velocities))) {
    const std::string vel = velocities.is_none() ? "" : pathArg(velocities, "velocities");
    py::gil_scoped_release release;
    r = eval::evaluateFiles(inputs.gt_path, inputs.est_path, options, vel);
  } else {
    const StampedTrajectory gt = trajectoryArg(gt_obj, "gt");
    const StampedTrajectory est = trajectoryArg(est_obj, "est");
    std::optional<std::vector<StampedTwist>> twists;
    if (!velocities.is_none())
      twists = isPath(velocities) ? readVelocities(pathArg(velocities, "velocities"))
                                  : twistsFromArray(velocities);
    py::gil_scoped_release release;
    r = eval::evaluate(gt, est, options);
    if (twists) eval::addVelocityErrors(r, gt, *twists, options);
  }
  py::dict out = parseJson(eval::evalJson(r, inputs));
  out["ate_rmse_m"] = r.ate.trans.rmse;
  out["ate_perc_of_path"] = r.gt_path_length_m > 0 ? 100.0 * r.ate.trans.rmse / r.gt_path_length_m : 0.0;
  // Associated positions: ground truth and the aligned estimate (M×3), for plots.
  const std::size_t n = r.pairs.size();
  py::array_t<double> p_gt({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  py::array_t<double> p_est({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  auto g = p_gt.mutable_unchecked<2>();
  auto e = p_est.mutable_unchecked<2>();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d aligned = r.alignment.apply(r.pairs.p_est[i]);
    for (py::ssize_t c = 0; c < 3; ++c) {
      g(static_cast<py::ssize_t>(i), c) = r.pairs.p_gt[i](c);
      e(static_cast<py::ssize_t>(i), c) = aligned(c);
    }
  }
  out["gt_positions"] = p_gt;
  out["aligned_est_positions"] = p_est;
  return out;
}

}  // namespace

void bindEvaluate(py::module_& m) {
  m.def("evaluate", &evaluate, py::arg("gt"), py::arg("est"), py::arg("align") = "sim3",
        py::arg("velocities") = py::none(), py::kw_only(), py::arg("align_frames") = -1,
        py::arg("rel_lengths") = std::vector<double>{}, py::arg("max_time_diff_s") = 0.02,
        R"doc(Evaluates an estimated trajectory against ground truth, as 'asynevo eval' does.

rpg_trajectory_evaluation's definitions (docs/method/evaluation.md): poses associated by time (pairs
closer than max_time_diff_s, greedy, each pose used once), Umeyama alignment, ATE of the aligned
positions, relative errors over sub-trajectories of 10 ... 50 % of the ground-truth path length.

Args:
  gt, est: TUM files (t tx ty tz qx qy qz qw) or N x 8 arrays in that layout (t in seconds), e.g.
    run()["groundtruth"] and run()["trajectory"].
  align: "sim3" (default, monocular), "se3", "posyaw" or "none".
  velocities: the estimate's twists (N x 7 array t vx vy vz wx wy wz, or a velocities.txt) for the
    velocity errors; None = skip them.
  align_frames: poses used for the alignment (-1 = all).
  rel_lengths: sub-trajectory lengths in metres (empty = 10 ... 50 % of the path).
  max_time_diff_s: association tolerance in seconds.

Returns:
  eval.json as a dict (association, alignment, ate {trans_m, rot_deg, scale_perc: {rmse, mean, median,
  std, min, max}}, relative_error {per_length, pooled}, velocity, warnings) plus
    ate_rmse_m: the ATE (RMSE of the aligned positions, m); ate_perc_of_path: the same in % of the
    ground-truth path length; gt_positions, aligned_est_positions: M x 3 associated positions.

Raises:
  asynevo.Error when nothing associates or fewer than 3 poses do (the message gives both time spans);
  ValueError for malformed arrays.
)doc");
}

}  // namespace asynevo::python
