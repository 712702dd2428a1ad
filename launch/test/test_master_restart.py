#!/usr/bin/env python3
"""The ROS master killed and started again under a running scanner. What recovers:
* scans through connections made before (a persistent /body_scan/capture client; the
  coordinator's persistent connections to the pairs; the pair clouds to Merge; the reports);
* the coordinator, Merge and the pole managers register their topics and services with the new
  master within seconds (MasterWatch), so new clients find /body_scan/capture and new
  subscribers find the publishers."""
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import threading
import time
import unittest

import rosgraph
import rostest

from test_record_replay import TIME_SCALE, wait_until  # same directory

POLES = ("pole_a", "pole_b", "pole_c")
PAIRS = [f"{pole}/pair_{i}" for pole in POLES for i in range(1, 5)]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class MasterRestart(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="master_restart_")
        self.port = free_port()
        os.environ["ROS_MASTER_URI"] = f"http://localhost:{self.port}"
        self.procs = []
        self.master = self.start("master", ["rosmaster", "--core", "-p", str(self.port)])
        self.assertTrue(self.wait(lambda: rosgraph.Master("/t").is_online(), 30))
        self.start("launch", ["roslaunch", "body_scan_launch", "full_scanner.launch", "gui:=false",
                              "body_model:=false", f"calibration_dir:={self.dir}/calibration",
                              f"pair_timeout:={10.0 * TIME_SCALE}",
                              f"scan_timeout:={60.0 * TIME_SCALE}"])

    def tearDown(self):
        for proc in reversed(self.procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
                try:
                    proc.wait(30)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait()
        shutil.rmtree(self.dir, ignore_errors=True)

    def start(self, name, cmd):
        log = open(os.path.join(self.dir, name + ".log"), "w")
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        self.procs.append(proc)
        return proc

    @staticmethod
    def wait(predicate, timeout, period=0.2):
        """Polls a condition only the master can answer (no event tells us)."""
        deadline = time.monotonic() + timeout * TIME_SCALE
        while time.monotonic() < deadline:
            try:
                if predicate():
                    return True
            except Exception:
                pass
            time.sleep(period)
        return False

    def test_scans_continue_and_nodes_register_again(self):
        import rospy
        from body_scan_msgs.msg import ScanReport, TimingGroups
        from body_scan_msgs.srv import Scan
        rospy.init_node("test_master_restart", disable_signals=True)
        cond, reports = threading.Condition(), {}

        def on_report(report):
            with cond:
                reports[report.scan_id] = report
                cond.notify_all()

        sub = rospy.Subscriber("/body_scan/scan_report", ScanReport, on_report, queue_size=10)
        rospy.wait_for_service("/body_scan/capture", timeout=180 * TIME_SCALE)
        self.assertTrue(wait_until(cond, lambda: sub.get_num_connections() > 0, 60))
        persistent = rospy.ServiceProxy("/body_scan/capture", Scan, persistent=True)

        def scan(proxy, label):
            response = proxy(0)
            sid = response.scan_id
            self.assertTrue(wait_until(cond, lambda: sid in reports, 60), f"{label}: no report")
            report = reports[sid]
            print(f"[ figure ] {label}: scan {sid}, {len(report.pairs_present)} pairs, "
                  f"missing {list(report.pairs_missing)}")
            self.assertTrue(response.success, response.message)
            self.assertEqual(sorted(report.pairs_present), sorted(PAIRS))

        scan(persistent, "before the restart")
        old_pid = self.master.pid
        os.killpg(old_pid, signal.SIGKILL)
        self.master.wait()
        restart = time.monotonic()
        self.master = self.start("master2", ["rosmaster", "--core", "-p", str(self.port)])
        self.assertTrue(self.wait(lambda: rosgraph.Master("/t").is_online(), 30))

        # Existing connections: the persistent capture client, pairs, clouds, reports.
        scan(persistent, "after the restart, through the connection made before")

        # The nodes register again: new clients and subscribers find them.
        master = rosgraph.Master("/test_master_restart")

        def registered():
            publishers, _, services = master.getSystemState()
            served = {name for name, _ in services}
            published = {name for name, _ in publishers}
            return ("/body_scan/capture" in served
                    and all(f"/{p}/driver/capture" in served for p in PAIRS)
                    and all(f"/{p}/scan_points" in published for p in PAIRS)
                    and "/body_scan/timing_groups" in published)

        self.assertTrue(self.wait(registered, 20), "the nodes did not register again")
        print(f"[ figure ] coordinator, Merge and the 3 pole managers registered again "
              f"{time.monotonic() - restart:.1f} s after the master restart")
        scan(rospy.ServiceProxy("/body_scan/capture", Scan), "a new client after the restart")
        groups = rospy.wait_for_message("/body_scan/timing_groups", TimingGroups, timeout=20 * TIME_SCALE)
        self.assertGreater(len(groups.groups), 0)


if __name__ == "__main__":
    rostest.rosrun("body_scan_launch", "master_restart", MasterRestart)
