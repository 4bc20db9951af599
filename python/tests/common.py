"""Shared paths of the Python module's tests (set by python/CMakeLists.txt for ctest)."""
import decimal
import os
import pathlib

SOURCE_DIR = pathlib.Path(os.environ.get("ASYNEVO_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = SOURCE_DIR / "tests" / "data"
WORK = pathlib.Path(os.environ.get("ASYNEVO_TEST_WORK", "/tmp/asynevo-python-tests"))
# The 3 s boxes/6dof sequence the ctest fixture python.simulate_fixture writes, and the run folder of
# 'asynevo run' on it (python.cli_run_fixture).
SIM = WORK / "sim_boxes"
CLI_RUN = WORK / "cli_run"
# The command line (set by ctest).
ASYNEVO_BIN = os.environ.get("ASYNEVO_BIN", str(SOURCE_DIR / "build" / "bin" / "asynevo"))


def assert_same_as_cli(test, trajectory, knot_t_ns):
    """The CLI's stamped_traj_estimate.txt (times with 9 decimals, poses in shortest round-trip form) holds
    exactly the knots `trajectory` (N x 8) at `knot_t_ns`."""
    import numpy as np

    rows = [line.split() for line in (CLI_RUN / "stamped_traj_estimate.txt").read_text().splitlines()
            if line.strip() and not line.startswith("#")]
    test.assertEqual(len(rows), len(trajectory))
    cli_t_ns = [int((decimal.Decimal(r[0]) * 10**9).to_integral_value()) for r in rows]
    np.testing.assert_array_equal(knot_t_ns, cli_t_ns)
    np.testing.assert_array_equal(trajectory[:, 1:], np.array([[float(v) for v in r[1:]] for r in rows]))


def ecd_text_events(path, limit=None):
    """Events of an ECD events.txt parsed here, independently of the C++ reader: decimal seconds rounded
    to the nearest ns (docs/architecture.md: text timestamps are converted exactly, rounding at the ns)."""
    rows = []
    with open(path) as f:
        for line in f:
            if limit is not None and len(rows) >= limit:
                break
            ts, x, y, p = line.split()
            t_ns = int((decimal.Decimal(ts) * 10**9).to_integral_value(rounding=decimal.ROUND_HALF_EVEN))
            rows.append((t_ns, int(x), int(y), 1 if int(p) == 1 else -1))
    return rows


def assert_same_landmarks_as_cli(test, landmarks):
    """The CLI's landmarks.ply (ascii: x y z observations id) holds exactly `landmarks` (a dict with
    landmarks, landmark_ids, landmark_observations), in the same order."""
    import numpy as np

    body = (CLI_RUN / "landmarks.ply").read_text().split("end_header\n", 1)[1]
    rows = [line.split() for line in body.splitlines() if line.strip()]
    test.assertEqual(len(rows), len(landmarks["landmarks"]))
    np.testing.assert_array_equal(landmarks["landmarks"], [[float(v) for v in r[:3]] for r in rows])
    np.testing.assert_array_equal(landmarks["landmark_observations"], [int(r[3]) for r in rows])
    np.testing.assert_array_equal(landmarks["landmark_ids"], [int(r[4]) for r in rows])
