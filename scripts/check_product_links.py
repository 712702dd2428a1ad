#!/usr/bin/python3
"""Check the installed product binaries: no simulator or evaluation library linked, no path into
the source checkout compiled in.

Usage: /usr/bin/python3 scripts/check_product_links.py INSTALL_PREFIX

Run it in the install space's environment (source INSTALL_PREFIX/setup.bash) so that ldd
resolves our libraries there. Two checks:
  * links: `ldd` of every product nodelet/plugin library (the <library path> entries of the
    plugin description files in INSTALL_PREFIX/share/*/) and of every product node
    (INSTALL_PREFIX/lib/*/*_node and PRODUCT_NODES) lists no simulator or evaluation library
    (body_scan_sim, *_eval*, *evaluation*, *simulated_scan*) and no unresolved library;
  * paths: no installed ELF file (libraries and executables) contains the absolute path of
    this checkout or a relative path to the data folder beside it: binaries find data through
    ros::package::getPath or arguments, never through source paths. Debug information is left
    out (a -g build, such as make sanitize's, names its sources there by design).
Prints one line per problem naming the file and the fix; exit status 1 on any problem.
"""

import glob
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Simulator and evaluation libraries: product code never links them (file names of libraries).
NON_PRODUCT_LIBRARY = re.compile(r"lib(body_scan_sim\w*|\w*_eval\w*|\w*evaluation\w*|"
                                 r"\w*simulated_scan\w*)\.so")
# Plugin libraries that are themselves the simulator's (the `sim` driver backend).
NON_PRODUCT_PLUGIN = re.compile(r"(^|_)sim(_|$)|simulat|_eval|evaluation")
# Product nodes and tools besides the *_node executables.
PRODUCT_NODES = ("body_scan_calib/world_alignment_publisher", "body_scan_merge/save_cloud",
                 "body_scan_calib/calibrate_camera", "body_scan_calib/calibrate_pair",
                 "body_scan_calib/align_world", "body_scan_calib/bag_to_calibration_folder",
                 "body_scan_calib/capture_calibration_views", "body_scan_merge/plan_timing_groups",
                 "body_gait_id/gait_gallery", "body_scan_driver/list_devices",
                 "body_scan_driver/measure_projector_latency")
# A relative path from the checkout to the data folder beside it.
FORBIDDEN_STRINGS = (os.path.join("..", "shared"),)


def is_elf(path):
    with open(path, "rb") as f:
        return f.read(4) == b"\x7fELF"


def plugin_libraries(prefix):
    """Installed product plugin libraries: (description file, library file)."""
    found = []
    for description in sorted(glob.glob(os.path.join(prefix, "share", "*", "*.xml"))):
        try:
            root = ET.parse(description).getroot()
        except ET.ParseError:
            continue
        libraries = [root] if root.tag == "library" else root.findall("library")
        for library in libraries:
            path = library.get("path")
            if not path or NON_PRODUCT_PLUGIN.search(os.path.basename(path)):
                continue
            found.append((description, os.path.join(prefix, path + ".so")))
    return found


def product_nodes(prefix):
    nodes = glob.glob(os.path.join(prefix, "lib", "*", "*_node"))
    nodes += [os.path.join(prefix, "lib", n) for n in PRODUCT_NODES]
    return sorted(n for n in nodes if os.path.isfile(n))


def check_links(prefix):
    problems = []
    targets = plugin_libraries(prefix)
    targets += [(None, n) for n in product_nodes(prefix)]
    if not targets:
        return ["no product libraries or nodes found under %s: install first "
                "(cmake --install build)" % prefix], 0
    for description, binary in targets:
        rel = os.path.relpath(binary, prefix)
        if not os.path.isfile(binary):
            problems.append("%s names %s, which is not installed: add it to an install(TARGETS) "
                            "rule" % (os.path.relpath(description, prefix), rel))
            continue
        out = subprocess.run(["ldd", binary], capture_output=True, text=True).stdout
        for line in out.splitlines():
            name = line.strip().split(" ")[0]
            if "not found" in line:
                problems.append("%s: ldd cannot resolve %s (run in the install space's "
                                "environment; is the library installed?)" % (rel, name))
            elif NON_PRODUCT_LIBRARY.fullmatch(name):
                problems.append("%s links %s, a simulator or evaluation library: product "
                                "nodes and nodelets must not link it (move the code that needs "
                                "it into a sim/eval library or tool)" % (rel, name))
    return problems, len(targets)


def check_strings(prefix, checkout):
    problems = []
    forbidden = [checkout.rstrip("/") + "/"] + list(FORBIDDEN_STRINGS)
    files = []
    for dirpath, _, filenames in os.walk(prefix):
        for f in filenames:
            path = os.path.join(dirpath, f)
            if os.path.isfile(path) and not os.path.islink(path) and is_elf(path):
                files.append(path)
    for path in sorted(files):
        with tempfile.TemporaryDirectory() as scratch:
            without_debug = os.path.join(scratch, "elf")
            subprocess.run(["objcopy", "--strip-debug", path, without_debug], check=True)
            out = subprocess.run(["strings", "-a", without_debug], capture_output=True,
                                 text=True).stdout
        hits = sorted({s for s in out.splitlines() for bad in forbidden if bad in s})
        for hit in hits:
            problems.append("%s contains the path %r: find data through ros::package::getPath or "
                            "an argument instead of a path compiled in"
                            % (os.path.relpath(path, prefix), hit))
    return problems, len(files)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    prefix = os.path.abspath(sys.argv[1])
    link_problems, n_linked = check_links(prefix)
    string_problems, n_files = check_strings(prefix, ROOT)
    for problem in link_problems + string_problems:
        print("check_product_links: " + problem)
    print("check_product_links: %d product libraries/nodes checked with ldd (%d problems), "
          "%d ELF files with strings (%d problems)"
          % (n_linked, len(link_problems), n_files, len(string_problems)))
    return 1 if link_problems or string_problems else 0


if __name__ == "__main__":
    sys.exit(main())
