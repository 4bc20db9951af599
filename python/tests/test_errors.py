"""Bad input: ValueError naming the array and the index; C++ errors as asynevo.Error with file and line."""
import pathlib
import tempfile
import unittest

import numpy as np

import asynevo
from common import DATA

CALIB = {"fx": 200.0, "fy": 200.0, "cx": 120.0, "cy": 90.0, "width": 240, "height": 180}


def events(n=5):
    return {"t": np.arange(n, dtype=np.int64) * 1000, "x": np.arange(n, dtype=np.uint16),
            "y": np.arange(n, dtype=np.uint16), "p": np.ones(n, dtype=np.int8), "width": 240, "height": 180}


class BadArrays(unittest.TestCase):
    def check(self, ev, *fragments):
        for entry in ("run", "stream"):
            with self.subTest(entry=entry), self.assertRaises(ValueError) as cm:
                if entry == "run":
                    asynevo.run(ev, calib=CALIB)
                else:
                    asynevo.Stream(CALIB).push(ev["t"], ev["x"], ev["y"], ev["p"])
            for fragment in fragments:
                self.assertIn(fragment, str(cm.exception))

    def test_mismatched_lengths(self):
        ev = events()
        ev["y"] = ev["y"][:4]
        self.check(ev, "y has 4 elements but t has 5")

    def test_unsorted_time(self):
        ev = events()
        ev["t"][3] = 0
        self.check(ev, "t is not sorted", "t[3] = 0", "t[2] = 2000")

    def test_float_time(self):
        ev = events()
        ev["t"] = ev["t"] * 1e-9
        self.check(ev, "t has dtype float64", "nanoseconds")

    def test_float_pixels(self):
        ev = events()
        ev["x"] = ev["x"].astype(np.float32)
        self.check(ev, "x has dtype float32")

    def test_pixels_outside_the_sensor(self):
        ev = events()
        ev["x"][2] = 240
        self.check(ev, "x[2] = 240", "outside the sensor", "width 240")
        ev = events()
        ev["y"] = ev["y"].astype(np.int32)
        ev["y"][4] = -1
        self.check(ev, "y[4] = -1", "height 180")

    def test_bad_polarity(self):
        ev = events()
        ev["p"][1] = 2
        self.check(ev, "p[1] = 2")

    def test_two_dimensional(self):
        ev = events()
        ev["x"] = ev["x"].reshape(5, 1)
        self.check(ev, "x must be one-dimensional")

    def test_accepted_variants(self):
        # bool polarities, 0 for OFF, int32 pixels, strided views
        s = asynevo.Stream(CALIB)
        t = np.arange(10, dtype=np.int64)
        s.push(t[::2], np.arange(10, dtype=np.int32)[::2], np.zeros(5, dtype=np.int64), np.array([True, False] * 2 + [True]))
        s.push(t[:0], t[:0], t[:0], t[:0])
        s.push([], [], [], [])  # empty lists are float64 arrays: nothing to misread
        self.assertEqual(s.stats["events"], 5)

    def test_calibration_size_must_match(self):
        ev = events()
        ev["width"], ev["height"] = 346, 260
        with self.assertRaises(ValueError) as cm:
            asynevo.run(ev, calib=CALIB)
        self.assertIn("240x180", str(cm.exception))

    def test_bad_arguments(self):
        with self.assertRaises(ValueError):
            asynevo.run(events(), calib=CALIB, backend="isam2")
        with self.assertRaises(ValueError):
            asynevo.evaluate(np.zeros((3, 7)), np.zeros((3, 8)))
        with self.assertRaises(ValueError):
            asynevo.Stream({"fx": 1.0})


class CppErrors(unittest.TestCase):
    def test_malformed_event_file_names_file_and_line(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = pathlib.Path(tmp) / "events.txt"
            path.write_text("0.001 1 2 1\n0.002 3 4 0\n0.003 five 6 1\n")
            with self.assertRaises(asynevo.InputError) as cm:
                asynevo.read_events(path)
            self.assertIn(f"{path}:3:", str(cm.exception))
            self.assertIsInstance(cm.exception, asynevo.Error)
            self.assertIsInstance(cm.exception, RuntimeError)

    def test_unknown_config_key(self):
        with self.assertRaises(asynevo.Error) as cm:
            asynevo.run(DATA / "ecd" / "shapes_rotation", config={"backend": {"no_such_key": 1}})
        self.assertIn("no_such_key", str(cm.exception))

    def test_out_of_range_config_value(self):
        with self.assertRaises(asynevo.ConfigError) as cm:
            asynevo.Stream(CALIB, config={"backend": {"knot_dt_ms": -5}})
        self.assertIn("knot_dt_ms", str(cm.exception))

    def test_camera_info_topic_needs_a_bag(self):
        with self.assertRaises(asynevo.InputError) as cm:
            asynevo.run(DATA / "ecd" / "shapes_rotation", camera_info_topic="/dvs/camera_info")
        self.assertIn("--camera-info-topic '/dvs/camera_info' names a topic of a ROS bag", str(cm.exception))

    def test_missing_calibration_file(self):
        with self.assertRaises(asynevo.InputError) as cm:
            asynevo.Stream("/nonexistent/calib.txt")
        self.assertIn("/nonexistent/calib.txt", str(cm.exception))


if __name__ == "__main__":
    unittest.main()
