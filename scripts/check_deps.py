#!/usr/bin/python3
"""Check that the Makefile's DEB_PACKAGES and the package.xml files agree.

Usage: /usr/bin/python3 scripts/check_deps.py [--junit FILE]

Every dependency key of every package.xml in the workspace (the top-level folders) is mapped to
the Debian bookworm packages that provide it: rosdep keys of system libraries through
ROSDEP_KEYS (rosdep's base.yaml, Debian column), ROS packages through ROS_PACKAGES (Debian's
own names for ROS, as `dpkg -S /usr/share/PKG/package.xml` shows). Keys of our own packages
are skipped. It fails, naming the package.xml, the key and the fix, when
  * a key is in neither table,
  * a Debian package a key needs is missing from DEB_PACKAGES (so `make deps` would not
    install what `rosdep install --from-paths . --ignore-src` does),
  * DEB_PACKAGES lists a package that no package.xml needs and MAKEFILE_ONLY does not explain.
With --junit FILE it also writes a JUnit XML (one test case per package.xml, one for the
Makefile's extra entries) for scripts/test_summary.py. Exit status 1 on any problem.
"""

import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET

from junit import write_junit

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# rosdep keys of system dependencies -> Debian bookworm packages (ros/rosdistro rosdep/base.yaml).
ROSDEP_KEYS = {
    "benchmark": ["libbenchmark-dev"],
    "cli11": ["libcli11-dev"],
    "eigen": ["libeigen3-dev"],
    "gtest": ["libgtest-dev"],
    "libceres-dev": ["libceres-dev"],
    "libembree-dev": ["libembree-dev"],
    "libopencv-contrib-dev": ["libopencv-contrib-dev"],
    "libopencv-dev": ["libopencv-dev"],
    "libpcl-all-dev": ["libpcl-dev"],
    "libsqlite3-dev": ["libsqlite3-dev"],
    "libusb-1.0-dev": ["libusb-1.0-0-dev"],
    "libuvc-dev": ["libuvc-dev"],
    "libx11-dev": ["libx11-dev"],
    "pkg-config": ["pkg-config"],
    "tinyxml2": ["libtinyxml2-dev"],
    "xvfb": ["xvfb"],
    "yaml-cpp": ["libyaml-cpp-dev"],
}

# ROS packages -> the Debian packages of their C++ and Python parts that we use.
ROS_PACKAGES = {
    "camera_calibration_parsers": ["libcamera-calibration-parsers-dev"],
    "catkin": ["catkin"],
    "diagnostic_msgs": ["libdiagnostic-msgs-dev", "python3-diagnostic-msgs"],
    "diagnostic_updater": ["libdiagnostic-updater-dev"],
    "dynamic_reconfigure": ["libdynamic-reconfigure-config-init-mutex-dev",
                            "python3-dynamic-reconfigure"],
    "geometry_msgs": ["libgeometry-msgs-dev"],
    "message_generation": ["ros-message-generation"],
    "message_runtime": ["ros-message-runtime"],
    "nodelet": ["libnodeletlib-dev", "libnodeletlib-tools"],
    "pluginlib": ["pluginlib-dev"],
    "rosbag": ["librosbag-dev", "python3-rosbag"],
    "roscpp": ["libroscpp-dev"],
    "roslaunch": ["python3-roslaunch"],
    "roslib": ["libroslib-dev"],
    "rospy": ["python3-rospy"],
    "rostest": ["librostest-dev", "python3-rostest"],
    "rviz": ["rviz"],
    "sensor_msgs": ["libsensor-msgs-dev", "python3-sensor-msgs"],
    "std_msgs": ["libstd-msgs-dev"],
    "std_srvs": ["libstd-srvs-dev"],
    "tf2_ros": ["libtf2-ros-dev"],
    "visualization_msgs": ["libvisualization-msgs-dev", "python3-visualization-msgs"],
}

# DEB_PACKAGES entries that no package.xml key covers, each with the reason it is there.
MAKEFILE_ONLY = {
    "ros-base-dev": "the ROS base set a ROS user has (rosout, roslaunch's runtime, tf2 tools); "
                    "the keys above name the parts we build against",
    "ros-core": "roscore, rostopic and rosservice: scripts/demo.sh and the README's commands",
    "rosbash": "rosrun and roscd: scripts/demo.sh and the README's commands",
    "opencv-doc": "OpenCV's sample chessboard images, read by body_scan_calib's "
                  "test_camera_calibration_images (no rosdep key)",
}

DEPENDENCY_TAGS = ("depend", "build_depend", "build_export_depend", "buildtool_depend",
                   "buildtool_export_depend", "exec_depend", "run_depend", "test_depend",
                   "doc_depend")


def workspace_manifests(root):
    """package.xml paths of the top-level folders, relative to root, sorted."""
    return sorted(os.path.join(d, "package.xml") for d in os.listdir(root)
                  if os.path.isfile(os.path.join(root, d, "package.xml")))


def makefile_packages(makefile):
    """The words of the Makefile's `DEB_PACKAGES :=` assignment (with its continuations)."""
    text = open(makefile).read()
    match = re.search(r"^DEB_PACKAGES\s*:?=((?:[^\n]*\\\n)*[^\n]*)", text, re.MULTILINE)
    if not match:
        raise SystemExit("check_deps: no `DEB_PACKAGES :=` assignment in %s" % makefile)
    return match.group(1).replace("\\\n", " ").split()


def check(root):
    """Return ({manifest: [problem]}, [makefile problem])."""
    manifests = workspace_manifests(root)
    parsed = {m: ET.parse(os.path.join(root, m)).getroot() for m in manifests}
    ours = {r.findtext("name").strip() for r in parsed.values()}
    deb_packages = makefile_packages(os.path.join(root, "Makefile"))
    listed = set(deb_packages)

    problems = {m: [] for m in manifests}
    needed = set()
    for manifest, xml in parsed.items():
        for element in xml:
            if element.tag not in DEPENDENCY_TAGS:
                continue
            key = (element.text or "").strip()
            declared = "<%s>%s</%s>" % (element.tag, key, element.tag)
            if key in ours:
                continue
            debs = ROSDEP_KEYS.get(key, ROS_PACKAGES.get(key))
            if debs is None:
                problems[manifest].append(
                    "%s declares %s, a key scripts/check_deps.py does not know: use a rosdep "
                    "key that exists for Noetic (rosdep/base.yaml of ros/rosdistro) or a ROS "
                    "package name, and add it with its Debian bookworm package(s) to "
                    "ROSDEP_KEYS or ROS_PACKAGES" % (manifest, declared))
                continue
            needed.update(debs)
            for deb in debs:
                if deb not in listed:
                    problems[manifest].append(
                        "%s declares %s (Debian: %s), but the Makefile's DEB_PACKAGES lacks "
                        "%s: add %s to DEB_PACKAGES" % (manifest, declared, " ".join(debs),
                                                         deb, deb))

    makefile_problems = []
    for deb in deb_packages:
        if deb not in needed and deb not in MAKEFILE_ONLY:
            makefile_problems.append(
                "Makefile: DEB_PACKAGES lists %s, which no package.xml needs: declare its rosdep "
                "key in the package.xml whose CMakeLists.txt or scripts use it, or remove it from "
                "DEB_PACKAGES, or explain it in MAKEFILE_ONLY of scripts/check_deps.py" % deb)
    for deb in sorted(set(MAKEFILE_ONLY) - listed):
        makefile_problems.append(
            "scripts/check_deps.py: MAKEFILE_ONLY explains %s, which DEB_PACKAGES does not list: "
            "remove it from MAKEFILE_ONLY" % deb)
    return problems, makefile_problems


def write_results(path, problems, makefile_problems):
    cases = [(m.replace("/package.xml", "").replace("/", "_") + "_package_xml", p)
             for m, p in problems.items()]
    cases.append(("makefile_deb_packages", makefile_problems))
    write_junit(path, "check_deps",
                [(name, 0.0, "\n".join(found) if found else None, "") for name, found in cases])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--junit", metavar="FILE", help="also write a JUnit XML result file")
    parser.add_argument("--root", default=ROOT, help="workspace root (default: this repository)")
    args = parser.parse_args()

    problems, makefile_problems = check(args.root)
    if args.junit:
        write_results(args.junit, problems, makefile_problems)
    found = [p for ps in problems.values() for p in ps] + makefile_problems
    for problem in found:
        print("check_deps: " + problem, file=sys.stderr)
    if found:
        print("check_deps: %d problem(s)" % len(found), file=sys.stderr)
        return 1
    print("check_deps: %d package.xml files agree with the Makefile's DEB_PACKAGES"
          % len(problems))
    return 0


if __name__ == "__main__":
    sys.exit(main())
