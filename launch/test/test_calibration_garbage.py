#!/usr/bin/env python3
"""A pair's calibration file replaced by garbage while the scanner runs: the next scan still has
that pair with the same cloud (its Triangulate keeps the last good calibration), the Triangulate
reports the bad file once on /rosout naming the pair, and it takes the restored file again."""
import os
import threading
import unittest

import rospy
import rostest

from test_record_replay import TIME_SCALE, wait_until  # same directory
from body_scan_msgs.msg import ScanReport
from body_scan_msgs.srv import Scan
from rosgraph_msgs.msg import Log

PAIR = "pole_a/pair_1"


class Events:
    def __init__(self):
        self.cond = threading.Condition()
        self.reports, self.logs = {}, []
        self.report_sub = rospy.Subscriber("/body_scan/scan_report", ScanReport, self.on_report,
                                           queue_size=10)
        rospy.Subscriber("/rosout", Log, self.on_log, queue_size=100)

    def on_report(self, report):
        with self.cond:
            self.reports[report.scan_id] = report
            self.cond.notify_all()

    def on_log(self, log):
        with self.cond:
            self.logs.append(log)
            self.cond.notify_all()

    def wait(self, predicate, timeout):
        return wait_until(self.cond, predicate, timeout)

    def log_with(self, level, *words):
        return [l for l in self.logs if l.level == level and all(w in l.msg for w in words)]


def replace(path, content):
    """Atomically, as a deployment tool would."""
    with open(path + ".new", "wb") as f:
        f.write(content)
    os.replace(path + ".new", path)


class CalibrationGarbage(unittest.TestCase):
    def scan(self, events):
        response = rospy.ServiceProxy("/body_scan/capture", Scan)(0)
        sid = response.scan_id
        self.assertTrue(events.wait(lambda: sid in events.reports, 60), f"no report for {sid}")
        report = events.reports[sid]
        self.assertIn(PAIR, report.pairs_present, report.message)
        return report.points_per_pair[list(report.pairs_present).index(PAIR)]

    def test_garbage_keeps_last_good_calibration(self):
        events = Events()
        path = rospy.get_param("~calibration_file")
        rospy.wait_for_service("/body_scan/capture", timeout=120 * TIME_SCALE)
        self.assertTrue(events.wait(lambda: events.report_sub.get_num_connections() > 0, 60))
        good_points = self.scan(events)
        with open(path, "rb") as f:
            good = f.read()

        replace(path, b"\x00\xff{{ not: [a calibration\n" + os.urandom(256))
        garbage_points = self.scan(events)
        complaint = lambda: events.log_with(Log.ERROR, PAIR, "keeping the last good calibration")
        self.assertTrue(events.wait(complaint, 10), "no error naming the bad calibration file")
        print(f"[ figure ] {PAIR}: {good_points} points before, {garbage_points} with the garbage "
              f"file; reported: {complaint()[0].msg}")
        self.assertLessEqual(abs(garbage_points - good_points), 0.01 * good_points)
        garbage_points = self.scan(events)  # reported once per change, not per scan
        self.assertEqual(len(complaint()), 1)

        replace(path, good)
        restored_points = self.scan(events)
        reload = lambda: events.log_with(Log.INFO, PAIR, "calibration reloaded")
        self.assertTrue(events.wait(reload, 10), "the restored file was not taken")
        self.assertLessEqual(abs(restored_points - good_points), 0.01 * good_points)


if __name__ == "__main__":
    rospy.init_node("test_calibration_garbage")
    rostest.rosrun("body_scan_launch", "calibration_garbage", CalibrationGarbage)
