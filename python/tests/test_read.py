"""asynevo.read_events against independently known contents of the bundled test files."""
import os
import pathlib
import subprocess
import tempfile
import unittest

import numpy as np

import asynevo
from common import ASYNEVO_BIN, DATA, ecd_text_events


class ReadEvents(unittest.TestCase):
    def test_ecd_folder_matches_the_text_file(self):
        folder = DATA / "ecd" / "shapes_rotation"
        ev = asynevo.read_events(folder)
        expected = ecd_text_events(folder / "events.txt")
        self.assertEqual(len(ev["t"]), len(expected))
        self.assertEqual(len(ev["t"]), 20000)
        self.assertEqual((ev["width"], ev["height"], ev["format"]), (240, 180, "ecd"))
        self.assertEqual(ev["t"].dtype, np.int64)
        self.assertEqual(ev["x"].dtype, np.uint16)
        self.assertEqual(ev["y"].dtype, np.uint16)
        self.assertEqual(ev["p"].dtype, np.int8)
        exp = np.array(expected, dtype=np.int64)
        np.testing.assert_array_equal(ev["t"], exp[:, 0])
        np.testing.assert_array_equal(ev["x"], exp[:, 1])
        np.testing.assert_array_equal(ev["y"], exp[:, 2])
        np.testing.assert_array_equal(ev["p"], exp[:, 3])
        self.assertEqual(int(ev["t"][0]), 2_097_134_001)
        self.assertEqual(ev["stats"]["events"], 20000)

    def test_rosbag_lz4_and_bz2_hold_the_documented_events(self):
        # tests/data/SOURCES.md: 350 events, t = 1.6e9 s + i us, pixel (i mod 240, i mod 180), ON for even i.
        i = np.arange(350, dtype=np.int64)
        for name in ("dvs_lz4.bag", "dvs_bz2.bag"):
            with self.subTest(bag=name):
                ev = asynevo.read_events(DATA / "rosbag" / name)
                self.assertEqual(ev["format"], "rosbag")
                np.testing.assert_array_equal(ev["t"], 1_600_000_000 * 10**9 + i * 1000)
                np.testing.assert_array_equal(ev["x"], i % 240)
                np.testing.assert_array_equal(ev["y"], i % 180)
                np.testing.assert_array_equal(ev["p"], np.where(i % 2 == 0, 1, -1))

    def test_every_event_equals_what_the_command_line_reader_writes(self):
        # 'asynevo convert' writes what the C++ reader delivers as ECD text (exact ns, 9 decimals).
        if not os.access(ASYNEVO_BIN, os.X_OK):
            self.skipTest(f"no command line at {ASYNEVO_BIN}")
        sources = [DATA / "ecd" / "slider_depth", DATA / "ecd" / "boxes_rotation" / "events.txt",
                   DATA / "rosbag" / "dvs_bz2.bag"]
        with tempfile.TemporaryDirectory() as tmp:
            for source in sources:
                with self.subTest(source=source.name):
                    text = pathlib.Path(tmp) / (source.name + ".txt")
                    subprocess.run([ASYNEVO_BIN, "convert", "--dataset", str(source), "--out", str(text)], check=True,
                                   stdout=subprocess.DEVNULL)
                    expected = np.array(ecd_text_events(text), dtype=np.int64)
                    ev = asynevo.read_events(source)
                    self.assertEqual(len(ev["t"]), len(expected))
                    got = np.stack([ev["t"], ev["x"], ev["y"], ev["p"]], axis=1).astype(np.int64)
                    np.testing.assert_array_equal(got, expected)

    def test_max_events_and_format(self):
        ev = asynevo.read_events(str(DATA / "ecd" / "poster_rotation" / "events.txt"), format="ecd", max_events=123)
        self.assertEqual(len(ev["t"]), 123)
        self.assertEqual(len(ev["p"]), 123)
        expected = ecd_text_events(DATA / "ecd" / "poster_rotation" / "events.txt", limit=123)
        np.testing.assert_array_equal(ev["t"], [r[0] for r in expected])

    def test_a_smaller_sensor_is_an_input_error_naming_the_line(self):
        with self.assertRaises(asynevo.InputError) as cm:
            asynevo.read_events(DATA / "ecd" / "shapes_rotation", sensor=(100, 100))
        self.assertIn("events.txt:", str(cm.exception))

    def test_a_rectification_map_is_for_dsec_files_only(self):
        ev = asynevo.read_events(DATA / "ecd" / "shapes_rotation", max_events=10, rectify_map="none")
        self.assertEqual(ev["rectify_map"], "")
        self.assertEqual(ev["stats"]["rectified_outside"], 0)
        with self.assertRaises(asynevo.InputError) as cm:
            asynevo.read_events(DATA / "ecd" / "shapes_rotation", rectify_map="/some/rectify_map.h5")
        self.assertIn("applies to DSEC-style HDF5 events only", str(cm.exception))

    def test_missing_file_names_it(self):
        with self.assertRaises(asynevo.InputError) as cm:
            asynevo.read_events("/nonexistent/events.txt")
        self.assertIn("/nonexistent", str(cm.exception))

    def test_help_is_documented(self):
        self.assertIn("int64 timestamps", asynevo.read_events.__doc__)
        for name in ("run", "evaluate", "check_events", "Stream", "Error", "InputError", "ConfigError"):
            self.assertTrue(getattr(asynevo, name).__doc__, name)


if __name__ == "__main__":
    unittest.main()
