"""asynevo.Stream: batches pushed in, poses polled; the same trajectory as run() on the same events."""
import threading
import unittest

import numpy as np

import asynevo
from common import CLI_RUN, SIM, assert_same_as_cli, assert_same_landmarks_as_cli


class StreamTest(unittest.TestCase):
    def test_batches_give_the_offline_trajectory(self):
        if not (CLI_RUN / "stamped_traj_estimate.txt").exists():
            self.skipTest(f"{CLI_RUN} is missing: run the ctest fixtures (ctest -L python)")
        ev = asynevo.read_events(SIM)
        s = asynevo.Stream(SIM / "calib.txt", sensor=(ev["width"], ev["height"]))
        self.assertEqual((s.width, s.height), (240, 180))
        n = len(ev["t"])
        rng = np.random.default_rng(7)
        cuts = np.sort(rng.choice(n, size=200, replace=False))  # uneven batches, some tiny
        parts, times, latest_seen = [], [], 0
        for a, b in zip(np.r_[0, cuts], np.r_[cuts, n]):
            s.push(ev["t"][a:b], ev["x"][a:b], ev["y"][a:b], ev["p"][a:b])
            polled = s.poll()
            parts.append(polled["trajectory"])
            times.append(polled["knot_t_ns"])
            latest = s.latest()
            if latest is not None:
                latest_seen += 1
                self.assertEqual(latest.shape, (8,))
                self.assertTrue(np.all(np.isfinite(latest)))
        self.assertGreater(latest_seen, 50)
        live = np.concatenate(parts)
        self.assertGreater(len(live), 10)  # poses came out while streaming, not only at the end
        s.finish()
        rest = s.poll()
        traj = np.concatenate([live, rest["trajectory"]])
        assert_same_as_cli(self, traj, np.concatenate(times + [rest["knot_t_ns"]]))
        self.assertEqual(s.stats["events"], n)
        self.assertTrue(s.stats["initialized"])
        assert_same_landmarks_as_cli(self, s.landmarks())
        with self.assertRaises(ValueError) as cm:
            s.push(ev["t"][-1:], ev["x"][-1:], ev["y"][-1:], ev["p"][-1:])
        self.assertIn("after finish()", str(cm.exception))

    def test_polling_from_another_thread_while_pushing(self):
        if not (SIM / "events.txt").exists():
            self.skipTest(f"{SIM} is missing: run the ctest fixtures (ctest -L python)")
        ev = asynevo.read_events(SIM)
        n = int(np.searchsorted(ev["t"], ev["t"][0] + 800_000_000))  # the first 0.8 s
        s = asynevo.Stream(SIM / "calib.txt")

        def pusher():
            for a in range(0, n, 20000):
                b = min(n, a + 20000)
                s.push(ev["t"][a:b], ev["x"][a:b], ev["y"][a:b], ev["p"][a:b])

        thread = threading.Thread(target=pusher)
        thread.start()
        seen, polled = set(), 0
        while thread.is_alive():
            seen.add(s.stats["events"])
            polled += len(s.poll()["trajectory"])
            s.latest()
        thread.join()
        self.assertGreater(len(seen), 2)  # the counters moved while the other thread pushed
        self.assertEqual(s.stats["events"], n)
        s.finish()
        self.assertGreater(polled + len(s.poll()["trajectory"]), 5)

    def test_an_earlier_batch_is_rejected_whole(self):
        s = asynevo.Stream({"fx": 200, "fy": 200, "cx": 120, "cy": 90, "width": 240, "height": 180})
        s.push(np.array([1000, 2000], dtype=np.int64), [1, 2], [3, 4], [1, 0])
        with self.assertRaises(ValueError) as cm:
            s.push(np.array([1500], dtype=np.int64), [1], [1], [1])
        self.assertIn("t[0] = 1500", str(cm.exception))
        self.assertEqual(s.stats["events"], 2)


if __name__ == "__main__":
    unittest.main()
