#!/usr/bin/python3
"""The full scanner from the install space: install the built tree, then run
`roslaunch body_scan_launch full_scanner.launch gui:=false` in an environment that sources only
the install space's setup.bash (plus a sanitizer build's runtime variables, if set), and check
that one scan publishes a merged cloud.

Usage: /usr/bin/python3 scripts/test_install_space.py BUILD_DIR [--installed] [--no-links]
           [--junit FILE]

BUILD_DIR is a configured and built catkin build tree whose CMAKE_INSTALL_PREFIX lies inside it
(make build: BUILD_DIR/install). Test cases (JUnit XML with --junit, for test_summary.py):
  install            `cmake --install BUILD_DIR` into a fresh install prefix (with --installed:
                     the prefix is used as installed, e.g. by `catkin_make --source . install`)
  environment        the install space's setup.bash alone: every package of this workspace
                     is found there by rospack, nothing points into the devel space
  full_scanner_cloud full_scanner.launch (sim backend, headless): /body_scan/capture yields a
                     merged cloud of at least MIN_POINTS points on /body_scan/cloud, no node died
  product_links      scripts/check_product_links.py on the install space
Exit status 1 if any case failed.
"""

import argparse
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time

from junit import write_junit

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MIN_POINTS = 100000
# Sanitizer builds run several times slower: `make sanitize` stretches every wait by this.
TIME_SCALE = float(os.environ.get("BODY_SCAN_TEST_TIME_SCALE", "1"))
SERVICE_TIMEOUT = 300.0 * TIME_SCALE  # s for /body_scan/capture to come up (12 pairs at once)
CLOUD_TIMEOUT = 240.0 * TIME_SCALE  # s from the capture request to the merged cloud
# What a sanitizer build's processes need to load and configure its runtime (`make sanitize`);
# passed through, as they are not part of what setup.bash provides.
SANITIZER_RUNTIME = ("LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS", "TSAN_OPTIONS")


class Failed(Exception):
    pass


def cache_value(build_dir, name):
    with open(os.path.join(build_dir, "CMakeCache.txt")) as cache:
        for line in cache:
            if line.startswith(name + ":"):
                return line.split("=", 1)[1].strip()
    raise Failed("%s is not set in %s/CMakeCache.txt: configure the build first (make build)"
                 % (name, build_dir))


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def install(build_dir, prefix, log_dir):
    if not os.path.realpath(prefix).startswith(os.path.realpath(build_dir) + os.sep):
        raise Failed("CMAKE_INSTALL_PREFIX is %s, outside the build tree: configure with "
                     "-DCMAKE_INSTALL_PREFIX=%s/install (make build does)" % (prefix, build_dir))
    shutil.rmtree(prefix, ignore_errors=True)  # stale files would hide a missing install rule
    log = os.path.join(log_dir, "install.log")
    with open(log, "w") as out:
        rc = subprocess.call(["cmake", "--install", build_dir], stdout=out, stderr=out)
    if rc != 0:
        raise Failed("cmake --install %s failed (exit %d); see %s" % (build_dir, rc, log))
    return "installed into %s (log: %s)" % (prefix, log)


def install_environment(prefix, devel, ros_home, port):
    """The environment of `source PREFIX/setup.bash` started from an almost empty one."""
    base = {"HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8",
            "ROS_HOME": ros_home, "ROS_LOG_DIR": os.path.join(ros_home, "log"),
            "ROS_MASTER_URI": "http://localhost:%d" % port}
    base.update({var: os.environ[var] for var in SANITIZER_RUNTIME if var in os.environ})
    out = subprocess.run(["bash", "-c", 'source "$1/setup.bash" && env -0', "_", prefix],
                         env=base, capture_output=True, check=True).stdout.decode()
    env = dict(item.split("=", 1) for item in out.split("\0") if "=" in item)
    for var in ("ROS_PACKAGE_PATH", "CMAKE_PREFIX_PATH", "LD_LIBRARY_PATH", "PYTHONPATH",
                "PKG_CONFIG_PATH", "PATH"):
        leaks = [p for p in env.get(var, "").split(":") if p.startswith(devel)]
        if leaks:
            raise Failed("%s of the install space's setup.bash contains the devel space (%s): "
                         "the build was configured with the devel space sourced; configure "
                         "from a clean shell" % (var, ":".join(leaks)))
    return env


def check_packages(env, prefix):
    packages = []
    for manifest in sorted(os.listdir(ROOT)):
        xml = os.path.join(ROOT, manifest, "package.xml")
        if os.path.isfile(xml):
            packages.append(re.search(r"<name>\s*(\S+)\s*</name>", open(xml).read()).group(1))
    for package in packages:
        found = subprocess.run(["rospack", "find", package], env=env, capture_output=True,
                               text=True).stdout.strip()
        expected = os.path.join(prefix, "share", package)
        if found != expected:
            raise Failed("rospack find %s gives %r, not the install space's %s: is the package "
                         "installed (catkin_package + install rules)?" % (package, found, expected))
    return "rospack finds %d packages in %s/share" % (len(packages), prefix)


def run_full_scanner(env, log_dir, port):
    calibration = os.path.join(log_dir, "calibration")
    launch_log = open(os.path.join(log_dir, "roslaunch.log"), "w")
    launch = subprocess.Popen(["roslaunch", "-p", str(port), "body_scan_launch",
                               "full_scanner.launch", "gui:=false",
                               "calibration_dir:=" + calibration], env=env, stdout=launch_log,
                              stderr=subprocess.STDOUT, start_new_session=True)
    echo = None
    try:
        start = time.time()
        while True:
            services = subprocess.run(["rosservice", "list"], env=env, capture_output=True,
                                      text=True).stdout.split()
            if "/body_scan/capture" in services:
                break
            if launch.poll() is not None:
                raise Failed("roslaunch exited (%d) before /body_scan/capture came up; see %s"
                             % (launch.returncode, launch_log.name))
            if time.time() - start > SERVICE_TIMEOUT:
                raise Failed("/body_scan/capture did not come up within %.0f s; see %s"
                             % (SERVICE_TIMEOUT, launch_log.name))
            time.sleep(1.0)
        up = time.time() - start
        # width x height of the first merged cloud (the data is not printed).
        echo = subprocess.Popen(["rostopic", "echo", "-n", "1", "--noarr", "/body_scan/cloud"],
                                env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                text=True)
        # Capture only once the master lists the subscriber, so the cloud cannot be missed.
        deadline = time.time() + 30.0
        while True:
            info = subprocess.run(["rostopic", "info", "/body_scan/cloud"], env=env,
                                  capture_output=True, text=True).stdout
            if "rostopic" in info.split("Subscribers:")[-1]:
                break
            if time.time() > deadline:
                raise Failed("rostopic echo /body_scan/cloud did not subscribe within 30 s: %s"
                             % info.strip())
            time.sleep(0.2)
        asked = time.time()
        call = subprocess.run(["rosservice", "call", "/body_scan/capture", "0"], env=env,
                              capture_output=True, text=True, timeout=CLOUD_TIMEOUT)
        if call.returncode != 0:
            raise Failed("rosservice call /body_scan/capture 0 failed: %s"
                         % (call.stdout + call.stderr).strip())
        try:
            out, _ = echo.communicate(timeout=max(1.0, CLOUD_TIMEOUT - (time.time() - asked)))
        except subprocess.TimeoutExpired:
            raise Failed("no merged cloud on /body_scan/cloud within %.0f s of the capture "
                         "request; see %s" % (CLOUD_TIMEOUT, launch_log.name))
        scanned = time.time() - asked
        fields = dict(re.findall(r"^(width|height): (\d+)$", out, re.MULTILINE))
        points = int(fields.get("width", 0)) * int(fields.get("height", 0))
        if points < MIN_POINTS:
            raise Failed("the merged cloud has %d points, fewer than %d: %s"
                         % (points, MIN_POINTS, out.strip()[-500:]))
        launch_log.flush()
        died = [line for line in open(launch_log.name) if "has died" in line]
        if died:
            raise Failed("a node died: %s(see %s)" % ("".join(died), launch_log.name))
        return ("merged cloud of %d points; capture service up after %.1f s, cloud %.1f s after "
                "the request (log: %s)" % (points, up, scanned, launch_log.name))
    finally:
        if echo is not None and echo.poll() is None:
            echo.kill()
        if launch.poll() is None:
            os.killpg(launch.pid, signal.SIGINT)
            try:
                launch.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(launch.pid, signal.SIGKILL)
                launch.wait()
        launch_log.close()


def check_links(env, prefix):
    result = subprocess.run([sys.executable, os.path.join(ROOT, "scripts",
                                                          "check_product_links.py"), prefix],
                            env=env, capture_output=True, text=True)
    if result.returncode != 0:
        raise Failed(result.stdout + result.stderr)
    return result.stdout.strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build_dir")
    parser.add_argument("--junit", metavar="FILE")
    parser.add_argument("--installed", action="store_true",
                        help="test CMAKE_INSTALL_PREFIX as it is, without installing")
    parser.add_argument("--no-links", action="store_true",
                        help="leave out the product_links case")
    args = parser.parse_args()
    build_dir = os.path.abspath(args.build_dir)
    log_dir = os.path.join(build_dir, "install_space_test")
    shutil.rmtree(log_dir, ignore_errors=True)
    os.makedirs(os.path.join(log_dir, "ros_home", "log"))

    cases = []
    state = {}

    def case(name, step):
        start = time.time()
        if any(c[2] is not None for c in cases):
            cases.append((name, 0.0, "not run: an earlier step failed", ""))
            return
        try:
            detail = step()
            cases.append((name, time.time() - start, None, detail))
            print("install_space: %s: ok (%.1f s): %s" % (name, time.time() - start, detail))
        except (Failed, subprocess.SubprocessError, OSError) as exc:
            cases.append((name, time.time() - start, str(exc), ""))
            print("install_space: %s: FAILED (%.1f s): %s" % (name, time.time() - start, exc))

    def environment():
        prefix = state["prefix"]
        state["port"] = free_port()
        state["env"] = install_environment(prefix, state["devel"],
                                           os.path.join(log_dir, "ros_home"), state["port"])
        return check_packages(state["env"], prefix)

    def setup():
        state["prefix"] = cache_value(build_dir, "CMAKE_INSTALL_PREFIX")
        state["devel"] = cache_value(build_dir, "CATKIN_DEVEL_PREFIX")
        if args.installed:
            if not os.path.isfile(os.path.join(state["prefix"], "setup.bash")):
                raise Failed("no setup.bash in %s: install first" % state["prefix"])
            return "using %s as installed" % state["prefix"]
        return install(build_dir, state["prefix"], log_dir)

    case("install", setup)
    case("environment", environment)
    case("full_scanner_cloud", lambda: run_full_scanner(state["env"], log_dir, state["port"]))
    if not args.no_links:
        case("product_links", lambda: check_links(state["env"], state["prefix"]))
    if args.junit:
        write_junit(args.junit, "install_space", cases)
    return 1 if any(c[2] is not None for c in cases) else 0


if __name__ == "__main__":
    sys.exit(main())
