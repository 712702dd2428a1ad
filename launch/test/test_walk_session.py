#!/usr/bin/env python3
"""Walk sessions end to end on the simulated full scanner (full_scanner.launch walk_scenes:=...).

The gallery: simulated people 0-5 enrolled from walk 0 (their full-scanner walk-level fits are
the test data in data/gallery_fits, so enrolment takes no scans). The walker: person ~person on
walk 1, the 4 poses taken at the coordinator's prompts (simulated_walker). /body_scan/capture_walk
scans them; the fitter fits the walk, gait_id_node identifies it. ~enrolled: the walk must be
identified as that person and accepted; otherwise (a stranger) it must be rejected. ~replay:
the walk is also recorded (record.launch) and replayed (replay.launch under /replay with the
fitter and recognizer), and the replay must give the same identity and score."""
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import unittest

import rospy
import rostest

from test_record_replay import TIME_SCALE, recorded_topics, wait_for_recorder  # same directory
from body_scan_msgs.msg import Identity, WalkProgress
from body_scan_msgs.srv import CaptureWalk, ListSubjects, RemoveSubject


class Identities:
    """Identities on one namespace."""

    def __init__(self, prefix):
        self.lock = threading.Lock()
        self.received = []
        rospy.Subscriber(prefix + "/body_gait/identity", Identity, self.on_identity,
                         queue_size=20)

    def on_identity(self, identity):
        with self.lock:
            self.received.append(identity)

    def walk(self, walk_id, timeout):
        deadline = time.time() + timeout * TIME_SCALE
        while time.time() < deadline and not rospy.is_shutdown():
            with self.lock:
                for identity in self.received:
                    if identity.kind == Identity.WALK and identity.walk_id == walk_id:
                        return identity
            time.sleep(0.1)
        return None

    def scans(self, walk_id):
        with self.lock:
            return sorted((i for i in self.received
                           if i.kind == Identity.SCAN and i.walk_id == walk_id),
                          key=lambda i: i.pose_index)


def enrol_gallery(work, person):
    """People 0-5 from their walk-0 fits (no scans), and the walker's 4 scenes of walk 1."""
    rospy.wait_for_service("/gait_id/list", timeout=60 * TIME_SCALE)
    remove = rospy.ServiceProxy("/gait_id/remove", RemoveSubject)
    for subject in rospy.ServiceProxy("/gait_id/list", ListSubjects)().subject_ids:
        remove(subject)  # a gallery left by an earlier run
    fits = os.path.join(work, "fits")
    shutil.rmtree(fits, ignore_errors=True)
    shutil.copytree(rospy.get_param("~gallery_fits"), fits)
    subprocess.check_call(["rosrun", "body_gait_id", "enroll_simulated_people", "--database",
                           rospy.get_param("~database"), "--people", "6", "--scanner", "full",
                           "--cache", fits, "--walk-scenes", os.path.join(work, "walk"),
                           "--scene-person", str(person), "--scene-trial", "1"])


def describe(identity):
    return "%s score %.3f (%s)" % (identity.name, identity.score,
                                   "accepted" if identity.accepted else "rejected")


class WalkSession(unittest.TestCase):
    def test_walk_session(self):
        work = rospy.get_param("~work")
        person = rospy.get_param("~person")
        enrolled = rospy.get_param("~enrolled")
        replay = rospy.get_param("~replay", False)
        name = "person_%03d" % person
        start = time.time()
        enrol_gallery(work, person)
        live = Identities("")
        progress = []
        rospy.Subscriber("/body_scan/walk_progress", WalkProgress,
                         lambda p: progress.append((p.state, p.pose_index)), queue_size=20)
        rospy.wait_for_service("/body_scan/capture_walk", timeout=60 * TIME_SCALE)

        record = None
        bag = os.path.join(work, "walk.bag")
        if replay:
            if os.path.exists(bag):
                os.remove(bag)
            record = subprocess.Popen(["roslaunch", "body_scan_launch", "record.launch",
                                       "bag:=" + bag])
            self.assertTrue(wait_for_recorder(recorded_topics() + ["/body_scan/walk_progress"],
                                              "/record_scans", 30),
                            "record.launch did not connect to every pair's pattern sets")
        try:
            walk = rospy.ServiceProxy("/body_scan/capture_walk", CaptureWalk)(
                walk_id=0, pause=-1.0, trigger=True)
            self.assertTrue(walk.success, walk.message)
            self.assertEqual(len(walk.scan_ids), 4)
            answer = live.walk(walk.walk_id, 120)
        finally:
            if record:
                time.sleep(1.0)  # the bag writer drains its queue
                record.send_signal(signal.SIGINT)
                record.wait(timeout=30 * TIME_SCALE)
        self.assertIsNotNone(answer, "no walk identity on /body_gait/identity")
        print("[ figure ] walk %d of %s: %s; rank-5 %s" % (
            walk.walk_id, name, describe(answer),
            ", ".join("%s %.2f" % s for s in zip(answer.ranked_names, answer.ranked_scores))))
        for scan in live.scans(walk.walk_id):
            print("[ figure ]   its scan %d (pose %d): %s" % (scan.scan_id, scan.pose_index,
                                                              describe(scan)))
        print("[ figure ] walk captured and identified in %.0f s" % (time.time() - start))
        self.assertEqual(answer.threshold, rospy.get_param("/gait_id/walk_accept_threshold"))
        self.assertEqual(len(answer.ranked_names), 5)
        self.assertEqual([s.pose_index for s in live.scans(walk.walk_id)], [1, 2, 3, 4])
        self.assertIn((WalkProgress.DONE, 4), progress)
        if enrolled:
            self.assertEqual(answer.name, name)
            self.assertTrue(answer.accepted, "the enrolled walker was rejected: " +
                            describe(answer))
        else:
            self.assertFalse(answer.accepted, "a stranger's walk was accepted: " +
                             describe(answer))
        if not replay:
            return

        replayed = Identities("/replay")
        player = subprocess.Popen(["roslaunch", "body_scan_launch", "replay.launch", "bag:=" + bag,
                                   "prefix:=/replay", "body_model:=true", "rate:=3",
                                   "scan_timeout:=%g" % (60.0 * TIME_SCALE),
                                   "gallery_database:=" + rospy.get_param("~database"),
                                   "calibration_dir:=" + rospy.get_param("~calibration_dir")])
        try:
            again = replayed.walk(walk.walk_id, 180)
        finally:
            player.send_signal(signal.SIGINT)
            player.wait(timeout=30 * TIME_SCALE)
        self.assertIsNotNone(again, "no walk identity on /replay/body_gait/identity")
        print("[ figure ] replayed walk %d: %s" % (again.walk_id, describe(again)))
        self.assertEqual(again.name, answer.name)
        self.assertEqual(again.accepted, answer.accepted)
        self.assertAlmostEqual(again.score, answer.score, places=9)
        self.assertEqual(again.ranked_names, answer.ranked_names)


if __name__ == "__main__":
    rospy.init_node("test_walk_session")
    rostest.rosrun("body_scan_launch", "walk_session", WalkSession, sys.argv)
