#!/usr/bin/env python3
"""Record a live scan with record.launch, replay the bag with replay.launch (under /replay, next
to the live scanner) and compare: the replayed merged cloud has the same point count and no
coordinate differs by more than 1 micrometre."""
import os
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from xmlrpc.client import ServerProxy

import rosbag
import rosgraph
import rospy
import rostest
from body_scan_msgs.msg import ScanReport
from body_scan_msgs.srv import Scan
from sensor_msgs.msg import PointCloud2


class Latest:
    """Merged clouds and scan reports on one namespace, matched by their common stamp."""

    def __init__(self, prefix):
        self.lock = threading.Lock()
        self.clouds, self.reports = {}, {}  # by stamp
        rospy.Subscriber(prefix + "/body_scan/scan_report", ScanReport, self.on_report)
        rospy.Subscriber(prefix + "/body_scan/cloud", PointCloud2, self.on_cloud)

    def on_cloud(self, cloud):
        with self.lock:
            self.clouds[cloud.header.stamp] = cloud

    def on_report(self, report):
        with self.lock:
            self.reports[report.header.stamp] = report

    def wait(self, scan_id, timeout):
        deadline = time.time() + timeout * TIME_SCALE
        while time.time() < deadline and not rospy.is_shutdown():
            with self.lock:
                for stamp, report in self.reports.items():
                    if report.scan_id == scan_id and stamp in self.clouds:
                        return self.clouds[stamp], report
            time.sleep(0.1)
        return None, None


def xyz(cloud):
    """Points as (x, y, z) tuples (fields x, y, z first as float32, point_step from the cloud)."""
    step = cloud.point_step
    data = bytes(cloud.data)
    return [struct.unpack_from("<3f", data, i) for i in range(0, len(data), step)]


# Sanitizer builds run several times slower: `make sanitize` stretches every wait by this.
TIME_SCALE = float(os.environ.get("BODY_SCAN_TEST_TIME_SCALE", "1"))


def wait_until(cond, predicate, timeout, poll=0.05):
    """Waits until predicate() holds, woken by cond's notifications and every `poll` s: a
    subscriber's connection count changes without any notification."""
    deadline = time.monotonic() + timeout * TIME_SCALE
    with cond:
        while not predicate():
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return False
            cond.wait(min(remaining, poll))
        return True


def recorded_topics():
    """The topics a scan must reach the bag on: every pair's pattern set and the scan reports."""
    pairs = rospy.get_param("/body_scan/scan_coordinator/pairs")
    return ["/%s/pattern_set" % p for p in pairs] + ["/body_scan/scan_report"]


def wait_for_recorder(topics, recorder, timeout):
    """Waits until every publisher of every topic has an open connection to `recorder`. The
    master lists a subscription before its publishers have connected, and a message published
    in between never reaches the subscriber, so the publishers' own bus info is asked."""
    master = rosgraph.Master(rospy.get_name())
    deadline = time.time() + timeout * TIME_SCALE
    while time.time() < deadline:
        publishers = dict(master.getSystemState()[0])
        if all(topic in publishers and all(connected_to(master, node, topic, recorder)
                                           for node in publishers[topic]) for topic in topics):
            return True
        time.sleep(0.2)
    return False


def connected_to(master, node, topic, subscriber):
    """Whether `node` has an open outbound connection to `subscriber` on `topic`."""
    try:
        code, _, bus_info = ServerProxy(master.lookupNode(node)).getBusInfo(rospy.get_name())
    except (OSError, rosgraph.MasterError):
        return False  # the node went away or is starting: the caller asks again
    # Each entry: connection id, peer, direction, transport, topic, connected (roscpp, rospy).
    return code == 1 and any(info[1] == subscriber and info[2] == "o" and info[4] == topic and
                             (len(info) < 6 or info[5]) for info in bus_info)


class RecordReplay(unittest.TestCase):
    def test_replay_gives_the_same_cloud(self):
        workdir = tempfile.mkdtemp(prefix="body_scan_replay_")
        bag = os.path.join(workdir, "scan.bag")
        calibration_dir = rospy.get_param("~calibration_dir")
        live, replay = Latest(""), Latest("/replay")
        rospy.wait_for_service("/body_scan/capture", timeout=60 * TIME_SCALE)

        record = subprocess.Popen(["roslaunch", "body_scan_launch", "record.launch",
                                   "bag:=" + bag])
        try:
            self.assertTrue(wait_for_recorder(recorded_topics(), "/record_scans", 30),
                            "record.launch did not connect to every pair's pattern sets")
            response = rospy.ServiceProxy("/body_scan/capture", Scan)(0)
            self.assertTrue(response.success, response.message)
            cloud, report = live.wait(response.scan_id, 120)
            self.assertIsNotNone(cloud, "no live merged cloud")
            time.sleep(2.0)  # the bag writer drains its queue
        finally:
            record.send_signal(signal.SIGINT)
            record.wait(timeout=30 * TIME_SCALE)
        with rosbag.Bag(bag) as recorded:
            sets = sum(1 for _ in recorded.read_messages(
                topics=["/%s/pattern_set" % p for p in report.pairs_present]))
        self.assertEqual(sets, len(report.pairs_present), "pattern sets in the bag")

        player = subprocess.Popen(["roslaunch", "body_scan_launch", "replay.launch",
                                   "bag:=" + bag, "prefix:=/replay",
                                   "scan_timeout:=%g" % (60.0 * TIME_SCALE),
                                   "calibration_dir:=" + calibration_dir])
        try:
            replayed, replayed_report = replay.wait(response.scan_id, 180)
        finally:
            player.send_signal(signal.SIGINT)
            player.wait(timeout=30 * TIME_SCALE)
        self.assertIsNotNone(replayed, "no replayed merged cloud on /replay/body_scan/cloud")
        self.assertEqual(replayed_report.pairs_present, report.pairs_present)

        live_points, replayed_points = xyz(cloud), xyz(replayed)
        print("[ figure ] live %d points, replayed %d points" % (len(live_points),
                                                                 len(replayed_points)))
        self.assertEqual(len(live_points), len(replayed_points))
        live_points.sort()
        replayed_points.sort()
        worst = max(abs(a - b) for p, q in zip(live_points, replayed_points) for a, b in zip(p, q))
        print("[ figure ] max coordinate difference %.3g m" % worst)
        self.assertLessEqual(worst, 1e-6)


if __name__ == "__main__":
    rospy.init_node("test_record_replay")
    rostest.rosrun("body_scan_launch", "record_replay", RecordReplay, sys.argv)
