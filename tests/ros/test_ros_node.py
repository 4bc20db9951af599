"""Tests of asynevo_ros_node with a real ROS master on the loopback interface (ctest -L ros).

PlayTest plays a simulated sequence into the node at real-time pace and compares its poses with
`asynevo run` on the same events; MalformedTest sends one message of each malformed kind and checks that
each is counted and skipped while the node keeps running; CameraInfoTest gives the node its calibration
on the camera_info topic. One class per process (ctest runs each alone): rospy joins one master only. Every process started here (master, node,
publisher) is stopped in the test's cleanup, whatever happens.

Environment (set by tests/ros/CMakeLists.txt): ASYNEVO_ROS_NODE, ASYNEVO_ROS_PUBLISHER, ASYNEVO_ROS_WORK
(the fixtures' folder: sim_boxes/ and cli_run/; each test's logs go to logs/<class>.<test>/ there).
"""
import json
import math
import os
import shutil
import signal
import socket
import subprocess
import threading
import time
import unittest

NODE = os.environ["ASYNEVO_ROS_NODE"]
PUBLISHER = os.environ["ASYNEVO_ROS_PUBLISHER"]
WORK = os.environ["ASYNEVO_ROS_WORK"]
SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def read_tum(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                rows.append([float(v) for v in line.split()])
    return rows


def wait_for(condition, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


class RosGraph(unittest.TestCase):
    """A master on 127.0.0.1 at a free port, the node, and this process as a rospy subscriber."""

    def setUp(self):
        # Logs of the master, the node and the publisher: kept in the build folder until the next run.
        self.tmp = os.path.join(WORK, "logs", f"{type(self).__name__}.{self._testMethodName}")
        shutil.rmtree(self.tmp, ignore_errors=True)
        os.makedirs(self.tmp)
        port = free_port()
        self.env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1",
                        ROS_HOSTNAME="127.0.0.1", ROS_HOME=self.tmp, ROS_LOG_DIR=self.tmp,
                        ROSCONSOLE_STDOUT_LINE_BUFFERED="1")  # the node's log lines as they come
        os.environ.update({k: self.env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME", "ROS_HOME",
                                                     "ROS_LOG_DIR")})
        self.master = self.start(["rosmaster", "--core", "-p", str(port)], "master")
        import rosgraph
        wait_for(lambda: rosgraph.Master("/asynevo_test").is_online(), 15, "the ROS master")
        self.lock = threading.Lock()
        self.messages = {"pose": [], "pose_final": [], "odometry": [], "tf": [], "stats": []}

    def start(self, args, name):
        log = open(os.path.join(self.tmp, name + ".log"), "w")
        self.addCleanup(log.close)
        proc = subprocess.Popen(args, env=self.env, stdout=log, stderr=subprocess.STDOUT)
        self.addCleanup(self.stop, proc)
        return proc

    @staticmethod
    def stop(proc):
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()

    def log(self, name):
        with open(os.path.join(self.tmp, name + ".log")) as f:
            return f.read()

    def start_node(self, *params, wait=True):
        self.node = self.start([NODE, "events:=/dvs/events", "__name:=asynevo", "_stats_period:=0.2", *params], "node")
        if wait:  # up and subscribed, or the test fails here with the node's log
            wait_for(lambda: self.node.poll() is not None or "events from /dvs/events" in self.log("node"), 20,
                     "the node to start")
            self.assertIsNone(self.node.poll(), "the node exited:\n" + self.log("node"))

    def subscribe(self):
        import rospy
        from geometry_msgs.msg import PoseStamped
        from nav_msgs.msg import Odometry
        from std_msgs.msg import String
        from tf2_msgs.msg import TFMessage
        rospy.init_node("asynevo_test", anonymous=True, disable_signals=True)

        def keep(key):
            def callback(msg):
                with self.lock:
                    self.messages[key].append(msg)
            return callback
        rospy.Subscriber("/asynevo/pose", PoseStamped, keep("pose"), queue_size=1000)
        rospy.Subscriber("/asynevo/pose_final", PoseStamped, keep("pose_final"), queue_size=1000)
        rospy.Subscriber("/asynevo/odometry", Odometry, keep("odometry"), queue_size=1000)
        rospy.Subscriber("/tf", TFMessage, keep("tf"), queue_size=1000)
        rospy.Subscriber("/asynevo/stats", String, keep("stats"), queue_size=100)
        self.addCleanup(rospy.signal_shutdown, "test done")

    def stats(self):
        with self.lock:
            return json.loads(self.messages["stats"][-1].data) if self.messages["stats"] else None

    def run_publisher(self, *args):
        proc = self.start([PUBLISHER, *args, "events:=/dvs/events"], "publisher")
        try:
            proc.wait(90)
        except subprocess.TimeoutExpired:
            self.fail("the event publisher did not finish within 90 s")
        self.assertEqual(proc.returncode, 0, self.log("publisher"))
        return self.log("publisher")

    def stop_node(self):
        """SIGINT: the node processes its queue, makes the last solve, publishes the last knots, exits 0."""
        self.node.send_signal(signal.SIGINT)
        try:
            self.node.wait(30)
        except subprocess.TimeoutExpired:
            self.fail("the node did not stop within 30 s of SIGINT")
        self.assertEqual(self.node.returncode, 0, self.log("node"))
        time.sleep(0.5)  # the last messages reach this subscriber


def stamp(msg):
    return msg.header.stamp.secs + msg.header.stamp.nsecs * 1e-9


def pose_row(p):
    return [p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
            p.orientation.w]


class PlayTest(RosGraph):
    def test_poses_match_the_offline_run(self):
        sim = os.path.join(WORK, "sim_boxes")
        offline = read_tum(os.path.join(WORK, "cli_run", "stamped_traj_estimate.txt"))
        self.assertGreater(len(offline), 10, "the offline run must have initialized")
        self.start_node("_calib:=" + os.path.join(sim, "camchain.yaml"))
        self.subscribe()
        started = time.monotonic()
        out = self.run_publisher("play", sim, "1.0", "5")
        published = int(out.split("published ")[1].split(" events")[0])
        wait_for(lambda: (self.stats() or {}).get("events_processed") == published, 60,
                 f"the node to process all {published} events")
        caught_up_s = time.monotonic() - started
        live_stats = self.stats()
        self.stop_node()
        final_stats = self.stats()
        with self.lock:
            final = [[stamp(m)] + pose_row(m.pose) for m in self.messages["pose_final"]]
            live = [[stamp(m)] + pose_row(m.pose) for m in self.messages["pose"]]
            odometry = list(self.messages["odometry"])
            tf = list(self.messages["tf"])
        print(f"\n{published} events; {len(live)} live poses, {len(final)} final poses (offline {len(offline)}); "
              f"backend lag max {live_stats['max_lag_s']:.3f} s; all processed {caught_up_s:.1f} s after the "
              f"publisher started")

        # Every event reached the estimator: nothing skipped, nothing dropped, none left in the queue.
        self.assertEqual(final_stats["events_processed"], published)
        self.assertEqual(final_stats["skipped_total"], 0)
        self.assertEqual(final_stats["dropped_overload"], 0)
        self.assertTrue(final_stats["initialized"])
        self.assertTrue(math.isfinite(final_stats["max_lag_s"]) and final_stats["max_lag_s"] > 0)

        # Final knots: those of `asynevo run` on the same events, one for one (the streaming API is the
        # offline pipeline's call order, so equal up to the text file's 17 digits).
        self.assertEqual(len(final), len(offline))
        for got, want in zip(final, offline):
            self.assertAlmostEqual(got[0], want[0], delta=1e-6)
            for a, b in zip(got[1:], want[1:]):
                self.assertTrue(math.isfinite(a))
                self.assertAlmostEqual(a, b, delta=1e-7, msg=f"knot at t = {want[0]}: {got} vs {want}")

        # Live poses: the window's newest knot when it is added, before later events refine it. Times
        # increase, every one is a knot time of the offline run, and its position is near that knot's.
        self.assertGreater(len(live), 10)
        self.assertEqual(len(odometry), len(live))
        self.assertEqual(len(tf), len(live))
        self.assertEqual(tf[-1].transforms[0].header.frame_id, "world")
        self.assertEqual(tf[-1].transforms[0].child_frame_id, "camera")
        self.assertEqual(odometry[-1].child_frame_id, "camera")
        offline_at = {round(row[0], 6): row for row in offline}
        path = sum(math.dist(a[1:4], b[1:4]) for a, b in zip(offline, offline[1:]))
        worst = 0.0
        for prev, row in zip(live, live[1:]):
            self.assertGreater(row[0], prev[0])
        for row in live:
            self.assertTrue(all(math.isfinite(v) for v in row), row)
            want = offline_at.get(round(row[0], 6))
            self.assertIsNotNone(want, f"live pose at t = {row[0]} is not at a knot time of the offline run")
            worst = max(worst, math.dist(row[1:4], want[1:4]))
        print(f"live vs final position: worst {worst:.4f} m over a {path:.3f} m path")
        self.assertLess(worst, 0.1 * path)


class MalformedTest(RosGraph):
    def test_malformed_messages_are_counted_and_skipped(self):
        self.start_node("_calib:=" + os.path.join(SOURCE, "tests/data/ecd/shapes_rotation/calib.txt"))
        self.subscribe()
        out = self.run_publisher("malformed")
        self.assertIn("published 9 messages", out)
        wait_for(lambda: (self.stats() or {}).get("messages_received") == 9, 20, "the node to receive 9 messages")
        s = self.stats()
        self.assertIsNone(self.node.poll(), "the node must keep running")
        self.assertEqual(s["messages_accepted"], 2)
        self.assertEqual(s["skipped_total"], 7)
        for reason in ("out_of_sensor", "time_backwards", "empty", "size_mismatch", "unsorted", "bad_time",
                       "decode_error"):
            self.assertEqual(s["skipped"][reason], 1, reason)
        wait_for(lambda: (self.stats() or {}).get("events_processed") == 200, 10, "the 200 valid events")
        self.stop_node()
        log = self.log("node")
        for reason in ("out_of_sensor", "time_backwards", "decode_error"):
            self.assertIn(f"({reason})", log)
        self.assertIn("pixel (240,", log)

    def test_no_calibration_is_a_clear_error(self):
        self.start_node(wait=False)
        self.node.wait(20)
        self.assertEqual(self.node.returncode, 2)
        self.assertIn("no calibration: set /asynevo/calib", self.log("node"))


class CameraInfoTest(RosGraph):
    def test_calibration_from_camera_info(self):
        import rospy
        from sensor_msgs.msg import CameraInfo
        self.start_node("_use_camera_info:=true")
        self.subscribe()
        pub = rospy.Publisher("/camera_info", CameraInfo, queue_size=10, latch=True)
        wait_for(lambda: pub.get_num_connections() > 0, 15, "the node to subscribe to /camera_info")
        info = CameraInfo(width=240, height=180, distortion_model="plumb_bob")
        pub.publish(info)  # K all zero: ROS's uncalibrated camera, rejected
        wait_for(lambda: (self.stats() or {}).get("camera_info_rejected") == 1, 10, "the rejected camera info")
        # The DAVIS240C calibration of the ECD (tests/data/ecd/*/calib.txt).
        info.K = [199.092366542, 0, 132.192071378, 0, 198.82882047, 110.712660011, 0, 0, 1]
        info.D = [-0.368436311798, 0.150947243557, -0.000296130534385, -0.000759431726241, 0]
        pub.publish(info)
        wait_for(lambda: "240x180 camera from the camera_info topic /camera_info" in self.log("node"), 10,
                 "the node to take the calibration")
        self.assertIn("fx 199.09 fy 198.83 cx 132.19 cy 110.71", self.log("node"))
        out = self.run_publisher("malformed")
        self.assertIn("published 9 messages", out)
        wait_for(lambda: (self.stats() or {}).get("messages_received") == 9, 20, "the node to receive 9 messages")
        self.assertEqual(self.stats()["messages_accepted"], 2)
        self.assertEqual(self.stats()["before_calibration"], 0)
        self.stop_node()


class LaunchTest(RosGraph):
    def test_launch_file_and_a_bag_written_by_ros(self):
        """The launch file of docs/guide/ros.md, and `rosbag play` of a bag ROS's own writer made: the bag's
        dvs_msgs/EventArray connection (type, MD5 sum) is accepted by the node's subscription."""
        self.env["ROS_PACKAGE_PATH"] = os.path.dirname(NODE)  # the build's package.xml: package "asynevo"
        self.env["ROSCONSOLE_STDOUT_LINE_BUFFERED"] = "1"
        calib = os.path.join(SOURCE, "tests/data/ecd/shapes_rotation/calib.txt")
        launch = self.start(["roslaunch", os.path.join(SOURCE, "apps/asynevo_ros/launch/asynevo.launch"),
                             "calib:=" + calib, "config:=" + os.path.join(SOURCE, "config/ecd.yaml")], "node")
        self.subscribe()
        wait_for(lambda: "events from /dvs/events" in self.log("node"), 20, "the launched node")
        # tests/data/rosbag/dvs_lz4.bag (tests/data/SOURCES.md): 350 events on /dvs/events in messages of
        # 100, 0 and 250 events, 240x180.
        self.start(["rosbag", "play", "--quiet", os.path.join(SOURCE, "tests/data/rosbag/dvs_lz4.bag")], "rosbag")
        wait_for(lambda: (self.stats() or {}).get("messages_received") == 3, 20, "the bag's 3 event messages")
        wait_for(lambda: (self.stats() or {}).get("events_processed") == 350, 10, "the bag's 350 events")
        s = self.stats()
        self.assertEqual(s["messages_accepted"], 2)
        self.assertEqual(s["skipped"]["empty"], 1)
        self.assertEqual(s["skipped_total"], 1)
        launch.send_signal(signal.SIGINT)
        launch.wait(30)
        self.assertIn("asynevo: finished:", self.log("node"))


if __name__ == "__main__":
    unittest.main()
