#!/usr/bin/env python3
"""The three poles as three hosts on this machine (root only): network namespaces bs_pole_a/b/c,
each with its own address on a bridge (10.77.0.11-13, the central host 10.77.0.1), made here and
removed at the end. The central host runs the master, Merge and the ScanCoordinator
(full_scanner.launch poles:=false); each pole's pole.launch runs inside its namespace with ROS_IP
set to its address. Then:

  1. scans single-host first (all in the central namespace) and distributed, --scans each:
     latency (capture call -> scan report), and the bytes per scan crossing each pole's link;
  2. takes pole_b's link down in the middle of a scan (after the first cloud arrives): the scan
     completes from the other poles; the link comes back and the next scan has all 12 pairs.

Writes a YAML report (--report, default build/distributed/distributed.yaml); exit 1 when a
distributed scan misses a pair, the link-down scan misses one of pole_a / pole_c, or pole_b does
not rejoin.

  sudo scripts/distributed_poles.py [--scans 5] [--report FILE]
"""
import argparse
import os
import signal
import subprocess
import sys
import threading
import time

from soak import free_port, percentile  # same directory

POLES = ("pole_a", "pole_b", "pole_c")
PAIRS = [f"{pole}/pair_{i}" for pole in POLES for i in range(1, 5)]
SUBNET = "10.77.0"
CENTRAL_IP = f"{SUBNET}.1"
BRIDGE = "bsbr0"


def pole_ip(index):
    return f"{SUBNET}.{11 + index}"


def namespace(pole):
    return f"bs_{pole}"


def host_link(pole):
    return f"bsv_{pole[-1]}"  # the bridge side of the pole's veth pair


def ip(*args, netns=None):
    cmd = (["ip", "netns", "exec", netns] if netns else []) + ["ip"] + list(args)
    subprocess.run(cmd, check=True)


def make_network():
    ip("link", "add", BRIDGE, "type", "bridge")
    ip("addr", "add", f"{CENTRAL_IP}/24", "dev", BRIDGE)
    ip("link", "set", BRIDGE, "up")
    for index, pole in enumerate(POLES):
        ns, link = namespace(pole), host_link(pole)
        ip("netns", "add", ns)
        ip("link", "add", link, "type", "veth", "peer", "name", "eth0", "netns", ns)
        ip("link", "set", link, "master", BRIDGE, "up")
        ip("addr", "add", f"{pole_ip(index)}/24", "dev", "eth0", netns=ns)
        ip("link", "set", "eth0", "up", netns=ns)
        ip("link", "set", "lo", "up", netns=ns)


def remove_network():
    for pole in POLES:
        subprocess.run(["ip", "netns", "del", namespace(pole)], stderr=subprocess.DEVNULL)
        subprocess.run(["ip", "link", "del", host_link(pole)], stderr=subprocess.DEVNULL)
    subprocess.run(["ip", "link", "del", BRIDGE], stderr=subprocess.DEVNULL)


def link_bytes(pole):
    """Bytes through the pole's link so far, both directions."""
    base = f"/sys/class/net/{host_link(pole)}/statistics"
    return sum(int(open(f"{base}/{d}_bytes").read()) for d in ("rx", "tx"))


class Launches:
    """roslaunch processes in their own process groups, stopped together."""

    def __init__(self, log_dir):
        self.log_dir, self.procs = log_dir, []

    def start(self, name, args, env, netns=None, program="roslaunch"):
        cmd = (["ip", "netns", "exec", netns] if netns else []) + [program] + args
        log = open(os.path.join(self.log_dir, f"{name}.log"), "w")
        self.procs.append(subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                                           start_new_session=True))

    def stop(self):
        for proc in self.procs:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
        for proc in self.procs:
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
        self.procs = []


class Scanner:
    """The test client: scan reports and pair clouds seen, under one condition."""

    def __init__(self):
        import rospy
        from body_scan_msgs.msg import PairCloud, ScanReport
        from body_scan_msgs.srv import Scan
        self.rospy = rospy
        self.cond = threading.Condition()
        self.reports, self.clouds = {}, set()
        self.subs = [rospy.Subscriber("/body_scan/scan_report", ScanReport, self.on_report,
                                      queue_size=10)]
        self.Scan = Scan

    def on_report(self, report):
        with self.cond:
            self.reports[report.scan_id] = report
            self.cond.notify_all()

    def wait(self, predicate, timeout):
        """Also re-checks every 50 ms: connection counts change without a notification."""
        deadline = time.monotonic() + timeout
        with self.cond:
            while not predicate():
                if time.monotonic() >= deadline:
                    return False
                self.cond.wait(min(deadline - time.monotonic(), 0.05))
            return True

    def ready(self, timeout):
        self.rospy.wait_for_service("/body_scan/capture", timeout=timeout)
        return self.wait(lambda: self.subs[0].get_num_connections() > 0, timeout)

    def scan(self, timeout=120, during=None):
        """One capture; returns (latency s, report, coordinator response). `during` runs once
        the coordinator has started (after the first group answered)."""
        capture = self.rospy.ServiceProxy("/body_scan/capture", self.Scan)
        result = {}
        start = time.monotonic()
        thread = threading.Thread(target=lambda: result.update(r=capture(0)))
        thread.start()
        if during:
            during()
        thread.join(timeout)
        response = result.get("r")
        if response is None:
            return None, None, None
        sid = response.scan_id
        if not self.wait(lambda: sid in self.reports, timeout):
            return None, None, response
        return time.monotonic() - start, self.reports[sid], response


def run_scans(scanner, count, label, figures):
    latencies, traffic, missing = [], [], 0
    for _ in range(count):
        before = {p: link_bytes(p) for p in POLES} if label == "distributed" else None
        latency, report, response = scanner.scan()
        if report is None or report.pairs_missing:
            missing += 1
            continue
        latencies.append(latency)
        if before is not None:
            traffic.append({p: link_bytes(p) - before[p] for p in POLES})
    figures[label] = {"latencies": latencies, "traffic": traffic, "missing": missing}
    print(f"{label}: {len(latencies)}/{count} complete scans, latency p50 "
          f"{percentile(latencies, 50) if latencies else float('nan'):.2f} s", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scans", type=int, default=5)
    parser.add_argument("--report", default=None)
    args = parser.parse_args()
    if os.geteuid() != 0:
        sys.exit("distributed_poles.py makes network namespaces: run it as root")
    signal.signal(signal.SIGTERM, lambda *_: sys.exit("distributed_poles: terminated"))

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = os.path.join(root, "build", "distributed")
    os.makedirs(out, exist_ok=True)
    report_path = args.report or os.path.join(out, "distributed.yaml")
    calibration = os.path.join(out, "calibration")
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://{CENTRAL_IP}:{port}", ROS_IP=CENTRAL_IP,
               ROS_HOME=os.path.join(out, "ros_home"))
    env.pop("ROS_HOSTNAME", None)
    os.environ.update({k: env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOME")})
    os.environ.pop("ROS_HOSTNAME", None)
    # The short pair and scan timeouts keep the link-down scan short; the rig is always planned
    # the same way (calibration files + the drivers' factory tf).
    central_args = ["body_scan_launch", "full_scanner.launch", "gui:=false",
                    "body_model:=false", f"calibration_dir:={calibration}", "pair_timeout:=3.0",
                    "scan_timeout:=15.0"]
    pole_args = lambda pole: ["body_scan_launch", "pole.launch", f"pole:={pole}",
                              f"calibration_dir:={calibration}"]
    figures, failures = {}, []
    launches = Launches(out)
    remove_network()  # left over from an interrupted run
    make_network()
    master = Launches(out)
    try:
        # One master for the whole run (this client stays registered with it).
        master.start("master", ["--core", "-p", str(port)], env, program="rosmaster")
        import rospy
        # 1. Single host: everything in the central namespace.
        launches.start("single_host", central_args, env)
        rospy.init_node("distributed_poles", anonymous=True, disable_signals=True)
        scanner = Scanner()
        if not scanner.ready(300):
            raise RuntimeError("single-host scanner did not come up")
        run_scans(scanner, args.scans, "single_host", figures)
        launches.stop()

        # 2. Distributed: the central host without poles, each pole in its namespace.
        launches.start("central", central_args + ["poles:=false"], env)
        for index, pole in enumerate(POLES):
            launches.start(pole, pole_args(pole), dict(env, ROS_IP=pole_ip(index)),
                           netns=namespace(pole))
        if not scanner.ready(300):
            raise RuntimeError("distributed scanner did not come up")
        run_scans(scanner, args.scans, "distributed", figures)
        if figures["distributed"]["missing"]:
            failures.append(f"{figures['distributed']['missing']} distributed scan(s) missed "
                            "a pair")

        # 3. pole_b's link down mid-scan, then up again.
        from body_scan_msgs.msg import PairCloud
        first_cloud = threading.Event()
        subs = [rospy.Subscriber(f"/{p}/scan_points", PairCloud,
                                 lambda _: first_cloud.set(), queue_size=1)
                for p in PAIRS if not p.startswith("pole_b")]
        scanner.wait(lambda: all(s.get_num_connections() > 0 for s in subs), 30)
        first_cloud.clear()

        def link_down():
            first_cloud.wait(60)
            ip("link", "set", host_link("pole_b"), "down")

        latency, report, response = scanner.scan(during=link_down)
        ip("link", "set", host_link("pole_b"), "up")
        for s in subs:
            s.unregister()
        if report is None:
            failures.append("the scan with pole_b's link down did not complete")
            figures["link_down"] = {"completed": False}
        else:
            others_missing = [p for p in report.pairs_missing if not p.startswith("pole_b")]
            if others_missing:
                failures.append(f"link down: other poles' pairs missing {others_missing}")
            figures["link_down"] = {"completed": True, "latency": latency,
                                    "missing": list(report.pairs_missing)}
        rejoin_start = time.monotonic()
        rejoined = None
        while time.monotonic() - rejoin_start < 120:  # each try is a full scan
            latency, report, _ = scanner.scan()
            if report is not None and not report.pairs_missing:
                rejoined = time.monotonic() - rejoin_start
                break
        figures["rejoin_seconds"] = rejoined
        if rejoined is None:
            failures.append("pole_b did not rejoin within 120 s of its link coming back")
    finally:
        launches.stop()
        master.stop()
        remove_network()

    lines = ["# scripts/distributed_poles.py: 3 poles in 3 network namespaces vs one host"]
    for label in ("single_host", "distributed"):
        f = figures.get(label)
        if not f or not f["latencies"]:
            continue
        lines.append(f"{label}_latency_seconds: {{p50: {percentile(f['latencies'], 50):.3f}, "
                     f"max: {max(f['latencies']):.3f}, scans: {len(f['latencies'])}, "
                     f"incomplete: {f['missing']}}}")
    traffic = figures.get("distributed", {}).get("traffic", [])
    if traffic:
        # The mean: the windows (capture call -> report) of the pole that delivers a scan's last
        # cloud shift by one cloud from scan to scan, so single windows (and their median) are
        # not per-scan figures.
        lines.append("bytes_per_scan_per_pole_link:  # mean over the scans, both directions")
        for pole in POLES:
            values = [t[pole] for t in traffic]
            lines.append(f"  {pole}: {int(sum(values) / len(values))}  # per window: {values}")
        total = sum(sum(t.values()) for t in traffic) / len(traffic)
        lines.append(f"bytes_per_scan_total: {int(total)}")
    if "link_down" in figures:
        lines.append(f"link_down: {figures['link_down']}")
    lines.append(f"rejoin_seconds: {figures.get('rejoin_seconds')}")
    lines.append("failures:")
    lines += [f"  - \"{f}\"" for f in failures]
    with open(report_path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
