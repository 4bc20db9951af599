"""asynevo.run and asynevo.evaluate on the fixture's simulated sequence (3 s, boxes, 6dof)."""
import pathlib
import tempfile
import unittest

import numpy as np

import asynevo
from common import CLI_RUN, SIM, assert_same_as_cli, assert_same_landmarks_as_cli


class Run(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not (CLI_RUN / "stamped_traj_estimate.txt").exists():
            raise unittest.SkipTest(f"{CLI_RUN} is missing: run the ctest fixtures (ctest -L python)")
        cls.result = asynevo.run(SIM)

    def test_trajectory_is_finite_and_accurate(self):
        r = self.result
        self.assertTrue(r["initialized"], r["message"])
        traj = r["trajectory"]
        self.assertEqual(traj.shape[1], 8)
        self.assertGreater(traj.shape[0], 40)  # knots every 50 ms from the start at ~0.4 s
        self.assertTrue(np.all(np.isfinite(traj)))
        self.assertTrue(np.all(np.diff(traj[:, 0]) > 0))
        np.testing.assert_allclose(np.linalg.norm(traj[:, 4:8], axis=1), 1.0, atol=1e-9)
        self.assertEqual(r["velocities"].shape, (traj.shape[0], 7))
        np.testing.assert_array_equal(r["knot_t_ns"] * 1e-9, traj[:, 0])
        self.assertGreater(r["landmarks"].shape[0], 20)
        self.assertEqual(r["landmarks"].shape[1], 3)
        self.assertEqual(r["stats"]["events"], r["stats"]["events"])  # parsed stats.json
        self.assertGreater(r["stats"]["events"], 100000)
        self.assertIsNone(r["out"])

        e = asynevo.evaluate(r["groundtruth"], traj)
        self.assertEqual(e["alignment"]["type"], "sim3")
        self.assertGreater(e["association"]["matched"], 40)
        # The CLI's end-to-end test bound (RunEndToEnd: ATE < 5 % of the path on this sequence).
        self.assertLess(e["ate_perc_of_path"], 5.0)
        self.assertAlmostEqual(e["ate_rmse_m"], e["ate"]["trans_m"]["rmse"])
        self.assertEqual(e["aligned_est_positions"].shape, e["gt_positions"].shape)

    def test_the_same_trajectory_as_the_command_line(self):
        assert_same_as_cli(self, self.result["trajectory"], self.result["knot_t_ns"])
        assert_same_landmarks_as_cli(self, self.result)

    def test_arrays_give_the_same_trajectory_as_the_dataset(self):
        ev = asynevo.read_events(SIM)
        r = asynevo.run(ev, calib=SIM / "calib.txt")
        np.testing.assert_array_equal(r["trajectory"], self.result["trajectory"])
        np.testing.assert_array_equal(r["landmarks"], self.result["landmarks"])
        self.assertIsNone(r["groundtruth"])

    def test_run_folder_and_evaluate_on_files_agree(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = pathlib.Path(tmp) / "run"
            ev = asynevo.read_events(SIM)
            # A tenth of a second: no estimate, but the run folder is written and initialization reported.
            short = {k: ev[k][ev["t"] < ev["t"][0] + 100_000_000] for k in "txyp"}
            short.update(width=ev["width"], height=ev["height"])
            r = asynevo.run(short, calib=SIM / "calib.txt", config={"backend": {"knot_dt_ms": 40}}, out=out)
            self.assertFalse(r["initialized"])
            self.assertIn("initialization never succeeded", r["message"])
            self.assertEqual(r["out"], str(out))
            self.assertTrue((out / "stats.json").exists())
            self.assertIn("knot_dt_ms: 40", (out / "config.yaml").read_text())
        gt = SIM / "groundtruth.txt"
        a = asynevo.evaluate(gt, self.result["groundtruth"], align="se3")
        self.assertLess(a["ate_rmse_m"], 1e-6)  # the ground truth against itself

    def test_evaluate_too_few_poses_is_an_error(self):
        with self.assertRaises(asynevo.Error):
            asynevo.evaluate(self.result["groundtruth"][:2], self.result["trajectory"][:2])


if __name__ == "__main__":
    unittest.main()
