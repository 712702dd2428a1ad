#!/usr/bin/env python3
"""Soak test of the whole scanner (make soak): full_scanner.launch headless on the simulated rig,
N consecutive scans through /body_scan/capture, each waited for on /body_scan/scan_report (and,
with the body model on, its fitted /body_gait/model).

Records per-scan latency (capture call -> scan report; p50/p99), the resident set size of every
node of the launch (from /proc) every --rss-every scans, and the missing scans. Fails (exit 1) on
any missing scan (no report within the deadline, or a report with missing pairs), on any node's
RSS growing more than --max-rss-growth over the run after the warm-up (rss_growth: the rise of
the floor of the samples from their second quarter to their last, as growth over the run), or on
p99 above
--max-p99-ratio x p50. Writes a YAML report (--report).

  scripts/soak.py [--scans 300] [--warmup 10] [--rss-every 5] [--report build/soak/soak.yaml]
                  [--launch-arg body_model:=false ...]
"""
import argparse
import os
import signal
import socket
import subprocess
import sys
import threading
import time


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def percentile(values, q):
    ordered = sorted(values)
    if not ordered:
        return float("nan")
    rank = q / 100.0 * (len(ordered) - 1)
    low = int(rank)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (rank - low)


def rss_growth(samples, warmup):
    """Growth of one node's RSS over the run after the warm-up, from (scan, KiB) samples taken
    at or after scan `warmup`: the rise of the floor (10th percentile) from the second quarter of
    the samples to the last, scaled from the distance between their centres to the whole span
    (a steady leak reads its growth over the run). None with fewer than 8 samples.
    A single reading swings up by what a node holds at that moment of a scan (a pole's pattern
    and cloud buffers, a fit's working memory not yet trimmed), so one reading against another
    measures the swing; the floor of a window is what the node returns to between scans, and a
    leak raises it. Allocators and buffers sized by the largest scan so far raise the floor in
    steps that level off (Merge's came at scan 55 in one run, by scan 75 in another): the first
    quarter is left out, so such a step early in the run is not read as growth, while a leak
    keeps its rate through the later quarters."""
    kept = [(scan, kib) for scan, kib in sorted(samples) if scan >= warmup and kib is not None]
    if len(kept) < 8:
        return None
    window = len(kept) // 4
    second, last = kept[window:2 * window], kept[-window:]
    rise = percentile([k for _, k in last], 10) / percentile([k for _, k in second], 10) - 1.0
    centres = (last[0][0] + last[-1][0]) / 2 - (second[0][0] + second[-1][0]) / 2
    return rise * (kept[-1][0] - kept[0][0]) / centres


def process_tree(root_pid):
    """{pid: ppid} of root_pid and all its descendants, from /proc."""
    parents = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        # The command name (2nd field) may hold spaces: the ppid is the 2nd field after ')'.
        parents[int(entry)] = int(stat.rsplit(")", 1)[1].split()[1])
    tree, frontier = {root_pid}, [root_pid]
    while frontier:
        pid = frontier.pop()
        for child, parent in parents.items():
            if parent == pid and child not in tree:
                tree.add(child)
                frontier.append(child)
    return tree


def node_name(pid):
    """The ROS name of a process started by roslaunch (__name:= and ROS_NAMESPACE), or None."""
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            argv = [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
        with open(f"/proc/{pid}/environ", "rb") as f:
            env = dict(
                e.decode(errors="replace").split("=", 1) for e in f.read().split(b"\0") if b"=" in e
            )
    except OSError:
        return None
    for arg in argv:
        if arg.startswith("__name:="):
            ns = env.get("ROS_NAMESPACE", "/").rstrip("/")
            return f"{ns}/{arg.split(':=', 1)[1]}"
    if any(os.path.basename(a) == "rosmaster" for a in argv[:2]):
        return "rosmaster"
    return None


def rss_kib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def node_rss(launch_pid):
    """{node name: RSS in KiB} of every ROS node process under the launch."""
    result = {}
    for pid in process_tree(launch_pid):
        name = node_name(pid)
        rss = rss_kib(pid) if name else None
        if name and rss is not None:
            result[name] = rss
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scans", type=int, default=300)
    parser.add_argument("--warmup", type=int, default=10,
                        help="scans before the RSS baseline (default 10)")
    parser.add_argument("--rss-every", type=int, default=5,
                        help="scans between RSS samples (default 5)")
    parser.add_argument("--scan-timeout", type=float, default=60.0,
                        help="s a scan may take from the capture call to its report")
    parser.add_argument("--max-rss-growth", type=float, default=0.05)
    parser.add_argument("--max-p99-ratio", type=float, default=2.0)
    parser.add_argument("--report", default=None, help="YAML report (default build/soak/soak.yaml)")
    parser.add_argument("--launch-arg", action="append", default=[],
                        help="extra full_scanner.launch arg, e.g. body_model:=false")
    args = parser.parse_args()
    # SIGTERM (e.g. timeout) unwinds through the finally that stops the launch.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit("soak: terminated"))

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out_dir = os.path.join(root, "build", "soak")
    os.makedirs(out_dir, exist_ok=True)
    report_path = args.report or os.path.join(out_dir, "soak.yaml")
    port = free_port()
    os.environ["ROS_MASTER_URI"] = f"http://localhost:{port}"
    os.environ.setdefault("ROS_HOME", os.path.join(out_dir, "ros_home"))
    os.makedirs(os.environ["ROS_HOME"], exist_ok=True)
    gallery = os.path.join(out_dir, "gait_gallery.db")
    for suffix in ("", "-wal", "-shm"):
        if os.path.exists(gallery + suffix):
            os.remove(gallery + suffix)
    launch_log = open(os.path.join(out_dir, "roslaunch.log"), "w")
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "body_scan_launch", "full_scanner.launch", "gui:=false",
         f"calibration_dir:={out_dir}/calibration", f"gallery_database:={gallery}"]
        + args.launch_arg,
        stdout=launch_log, stderr=subprocess.STDOUT, start_new_session=True)

    import rospy  # after ROS_MASTER_URI is set
    from body_scan_msgs.msg import BodyModel, ScanReport
    from body_scan_msgs.srv import Scan

    body_model = "body_model:=false" not in args.launch_arg
    failures = []
    try:
        deadline = time.monotonic() + 300
        while True:  # the master comes up with roslaunch
            try:
                rospy.init_node("soak", anonymous=True, disable_signals=True)
                break
            except Exception:
                pass
            if time.monotonic() > deadline or launch.poll() is not None:
                raise RuntimeError("no ROS master came up (see build/soak/roslaunch.log)")
            time.sleep(0.2)
        cond = threading.Condition()
        reports, models = {}, {}

        def keep(store, key):
            def callback(message):
                with cond:
                    store[key(message)] = (time.monotonic(), message)
                    cond.notify_all()
            return callback

        watched = [rospy.Subscriber("/body_scan/scan_report", ScanReport,
                                    keep(reports, lambda m: m.scan_id), queue_size=10)]
        watched.append(rospy.Subscriber("/body_gait/model", BodyModel, keep(models, lambda m: m.header.stamp),
                                        queue_size=10))
        if not body_model:
            watched.pop()
        rospy.wait_for_service("/body_scan/capture", timeout=300)
        capture = rospy.ServiceProxy("/body_scan/capture", Scan, persistent=True)

        def wait_for(predicate, until):
            with cond:
                while not predicate():
                    remaining = until - time.monotonic()
                    if remaining <= 0:
                        return False
                    cond.wait(remaining)
                return True

        # The report (and model) publishers must be connected to us before the first scan.
        deadline = time.monotonic() + 120
        while any(s.get_num_connections() == 0 for s in watched):
            if time.monotonic() > deadline:
                raise RuntimeError("/body_scan/scan_report or /body_gait/model never connected")
            time.sleep(0.1)

        latencies, fit_latencies, missing, rss_warm, rss_samples = [], [], [], None, []
        start_all = time.monotonic()
        for i in range(1, args.scans + 1):
            start = time.monotonic()
            try:
                response = capture(0)
            except Exception as e:  # the coordinator died or the call broke
                missing.append({"scan": i, "why": f"capture call failed: {e}"})
                capture = rospy.ServiceProxy("/body_scan/capture", Scan, persistent=True)
                continue
            sid = response.scan_id
            if not wait_for(lambda: sid in reports, start + args.scan_timeout):
                missing.append({"scan": sid, "why": "no scan report within the deadline"})
                continue
            arrived, report = reports.pop(sid)
            latencies.append(arrived - start)
            if report.pairs_missing or not response.success:
                missing.append({"scan": sid, "why": "pairs missing: " + " ".join(
                    sorted(set(report.pairs_missing) | set(response.pairs_missing)))})
            if body_model:
                stamp = report.header.stamp
                if not wait_for(lambda: stamp in models, start + args.scan_timeout):
                    missing.append({"scan": sid, "why": "no fitted body model in time"})
                else:
                    fit_latencies.append(models.pop(stamp)[0] - start)
            if i == args.warmup:
                rss_warm = node_rss(launch.pid)
                rss_samples.append((i, rss_warm))
            elif i > args.warmup and ((i - args.warmup) % args.rss_every == 0 or i == args.scans):
                rss_samples.append((i, node_rss(launch.pid)))
            if i % 25 == 0 or i == args.scans:
                print(f"scan {i}/{args.scans}: latency p50 {percentile(latencies, 50):.3f} s, "
                      f"{len(missing)} missing", flush=True)
        rss_end = node_rss(launch.pid)
        wall = time.monotonic() - start_all
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)
            launch.wait()

    p50, p99 = percentile(latencies, 50), percentile(latencies, 99)
    lines = [
        "# scripts/soak.py: full_scanner.launch headless (simulated rig), consecutive scans",
        f"scans_requested: {args.scans}",
        f"scans_reported: {len(latencies)}",
        f"scans_missing: {len(missing)}",
        f"wall_seconds: {wall:.1f}",
        f"latency_seconds: {{p50: {p50:.4f}, p99: {p99:.4f}, max: {max(latencies or [0]):.4f}}}",
    ]
    if fit_latencies:
        lines.append("capture_to_body_model_seconds: {p50: %.4f, p99: %.4f}" % (
            percentile(fit_latencies, 50), percentile(fit_latencies, 99)))
    lines.append(f"rss_kib:  # node: [after scan {args.warmup}, at the end, growth over the run "
                 f"at the rate from the second to the last quarter (rss_growth), samples every "
                 f"{args.rss_every} scans]")
    for name in sorted(set(rss_warm or {}) | set(rss_end)):
        warm, end = (rss_warm or {}).get(name), rss_end.get(name)
        growth = rss_growth([(scan, rss.get(name)) for scan, rss in rss_samples], args.warmup)
        lines.append(f"  {name}: [{warm}, {end}, "
                     f"{'null' if growth is None else format(growth, '+.4f')}]")
        if warm is None or end is None or growth is None:
            failures.append(f"{name}: not running from scan {args.warmup} to the end")
        elif growth > args.max_rss_growth:
            failures.append(f"{name}: RSS grows {100 * growth:.1f} % over the run at the rate "
                            f"from its second to its last quarter")
    # Every sample of the nodes above 50 MB: a leak climbs, an allocator's high-water mark levels.
    big = sorted(n for n, kib in rss_end.items() if kib > 50 * 1024)
    lines.append("rss_trace_kib:  # scan: RSS of " + ", ".join(big))
    lines += [f"  {scan}: [{', '.join(str(rss.get(n)) for n in big)}]" for scan, rss in rss_samples]
    with open(os.path.join(os.path.dirname(report_path), "rss_samples.yaml"), "w") as f:
        f.write("# scan: {node: RSS KiB}\n")
        f.writelines(f"{scan}: {dict(sorted(rss.items()))}\n" for scan, rss in rss_samples)
    lines.append("missing:")
    lines += [f"  - {{scan: {m['scan']}, why: \"{m['why']}\"}}" for m in missing]
    if missing:
        failures.append(f"{len(missing)} missing scan(s)")
    if len(latencies) < 2 or p99 > args.max_p99_ratio * p50:
        failures.append(f"latency p99 {p99:.3f} s > {args.max_p99_ratio} x p50 {p50:.3f} s")
    lines.append("failures:")
    lines += [f"  - \"{f}\"" for f in failures]
    with open(report_path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"soak {'FAILED' if failures else 'passed'}; report {report_path}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
