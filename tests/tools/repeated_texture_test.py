#!/usr/bin/python3
"""Unit tests of tools/repeated_texture.py (the repeated-texture experiment's evaluation): the per-phase
errors, the ground-truth velocity and the pose differencing on synthetic data (no binary needed, ~1 s;
registered with ctest in tests/tools/CMakeLists.txt)."""

import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tool_checks import check, exit_code  # noqa: E402

import numpy as np  # noqa: E402

import repeated_texture as rt  # noqa: E402


def write(path, rows):
    with open(path, "w") as f:
        for r in rows:
            f.write(" ".join("%.9f" % x for x in r) + "\n")


def main():
    # Per phase: an estimate 10 % slow along x at 2 m/s in [0, 1), exact in [1, 2), and 1 m/s off along y
    # at 3 m/s in [2, 3).
    t = np.arange(0.0, 3.0, 0.1)
    v_gt = np.zeros((len(t), 3))
    v_gt[:, 0] = np.where(t < 1, 2.0, 3.0)
    v_est = v_gt.copy()
    v_est[t < 1, 0] = 1.8
    v_est[t >= 2, 1] = 1.0
    phases = {"slow": (0.0, 1.0), "accelerating": (1.0, 2.0), "fast": (2.0, 3.0)}
    e = rt.phase_errors(t, v_est, v_gt, phases)
    check(abs(e["slow"]["velocity_rmse_mps"] - 0.2) < 1e-12 and abs(e["slow"]["speed_rmse_perc"] - 10.0) < 1e-9,
          "10 %% slow: velocity RMSE 0.2 m/s, speed error 10 %%: %s" % e["slow"])
    check(e["accelerating"]["velocity_rmse_mps"] == 0.0, "an exact phase has no error")
    check(abs(e["fast"]["velocity_rmse_mps"] - 1.0) < 1e-12
          and abs(e["fast"]["speed_rmse_perc"] - (np.sqrt(10.0) - 3.0) / 3.0 * 100) < 1e-9,
          "a sideways error counts fully in the velocity, as sqrt(10) - 3 in the speed: %s" % e["fast"])
    check(rt.phase_errors(t, v_est, v_gt, {"none": (5.0, 6.0)})["none"] is None, "an empty phase is None")

    with tempfile.TemporaryDirectory() as tmp:
        # Ground truth at 1 kHz along x at x(t) = t² (v = 2t), identity rotation.
        tg = np.arange(0.0, 2.0005, 0.001)
        write(os.path.join(tmp, "gt.txt"), [[s, s * s, 0, 0, 0, 0, 0, 1] for s in tg])
        gt = rt.GroundTruth(os.path.join(tmp, "gt.txt"))
        v = gt.velocity_body(np.array([0.5, 1.5]))
        check(np.allclose(v[:, 0], [1.0, 3.0], atol=1e-6) and np.allclose(v[:, 1:], 0),
              "central differences give v = 2t: %s" % v)
        # A run at half the scale: poses x = t²/2 every 50 ms, twists v = t; Sim(3) scale 2 in both evals.
        run = os.path.join(tmp, "run")
        for name in ("eval_all", "eval_slow"):
            os.makedirs(os.path.join(run, name))
            with open(os.path.join(run, name, "eval.json"), "w") as f:
                json.dump({"alignment": {"scale": 2.0, "rotation": np.eye(3).tolist(), "translation": [0, 0, 0]}}, f)
        tk = np.arange(0.0, 2.0001, 0.05)
        write(os.path.join(run, "stamped_traj_estimate.txt"), [[s, s * s / 2, 0, 0, 0, 0, 0, 1] for s in tk])
        write(os.path.join(run, "velocities.txt"), [[s, s, 0, 0, 0, 0, 0] for s in tk])
        r = rt.Run(run)
        tt, vt = r.twist_speed("slow")
        check(np.allclose(vt[:, 0], 2 * tk), "twists are scaled by the alignment's scale")
        tm, vd = r.differenced("all")
        check(np.allclose(tm, tk[:-1] + 0.025) and np.allclose(vd[:, 0], 2 * tm, atol=1e-9),
              "differenced poses give the speed at the midpoints (exact for a parabola)")
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())
