#!/usr/bin/python3
"""Summarise the JUnit XML results of `make -C build run_tests` (gtest and rostest).

Usage: /usr/bin/python3 scripts/test_summary.py [RESULTS_DIR] [--write FILE]

Walks RESULTS_DIR (default: build/test_results next to this script's parent) for *.xml
files and counts every <testcase>:
  * failed  -- it has a <failure> or <error> child;
  * skipped -- it has a <skipped> child, or gtest marked it status="notrun" or
               result="skipped"/"suppressed" (GTEST_SKIP, DISABLED_ tests);
  * passed  -- otherwise.
Special cases:
  * catkin's MISSING-*.xml (written when a test binary crashed or wrote no results) holds a
    failing testcase, so it counts as failed like any other failure;
  * a file that is not valid XML counts as one failure;
  * a file without testcases whose <testsuite>/<testsuites> declares failures or errors
    counts as that many failures;
  * rostest-*.xml files are rostest's wrappers: they hold one testcase per <test> node that
    only checks that the node ran and reported; its real cases are in rosunit-*.xml next to
    it. A wrapper's passes are therefore not counted (they would double-count), while its
    failures, errors and skips are.

Prints one `FAILED: suite.case (file)` line per failure, followed by the first lines of its
failure message (indented), then as the very last line
`N passed, N failed, N skipped`. With --write FILE the
last line is also written to FILE. Exit status 1 if anything failed or nothing ran.
"""

import argparse
import os
import sys
import xml.etree.ElementTree as ET

SKIP_RESULTS = {"skipped", "suppressed"}


def classify(case):
    """Return 'failed', 'skipped' or 'passed' for one <testcase> element."""
    if case.find("failure") is not None or case.find("error") is not None:
        return "failed"
    if (case.find("skipped") is not None or case.get("status") == "notrun"
            or case.get("result") in SKIP_RESULTS):
        return "skipped"
    return "passed"


def declared_failures(root):
    """Failures + errors declared by the (first level of) suite elements of a file."""
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite") or [root]
    total = 0
    for suite in suites:
        for attr in ("failures", "errors"):
            try:
                total += int(suite.get(attr, "0") or 0)
            except ValueError:
                pass
    return total


def summarise(results_dir):
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    failures = []
    xml_files = []
    for dirpath, dirnames, filenames in os.walk(results_dir):
        dirnames.sort()
        xml_files += [os.path.join(dirpath, f) for f in sorted(filenames) if f.endswith(".xml")]

    for path in xml_files:
        rel = os.path.relpath(path, results_dir)
        wrapper = os.path.basename(path).startswith("rostest-")
        try:
            root = ET.parse(path).getroot()
        except (ET.ParseError, OSError) as exc:
            counts["failed"] += 1
            failures.append("FAILED: unreadable result file: %s (%s)" % (exc, rel))
            continue

        cases = list(root.iter("testcase"))
        if not cases:
            n = declared_failures(root)
            if n:
                counts["failed"] += n
                failures.append("FAILED: %s (%s)" % (root.get("name", "?"), rel))
            continue

        for case in cases:
            outcome = classify(case)
            if wrapper and outcome == "passed":
                continue
            counts[outcome] += 1
            if outcome == "failed":
                if os.path.basename(path).startswith("MISSING-"):
                    what = "%s (crashed or wrote no results)" % root.get("name", "?")
                else:
                    what = "%s.%s" % (case.get("classname") or root.get("name") or "?",
                                      case.get("name", "?"))
                failures.append("FAILED: %s (%s)" % (what, rel))
                failures += failure_detail(case)
    return counts, failures


def failure_detail(case, max_lines=12):
    """The first lines of a failed case's message, indented, so a CI log shows why."""
    lines = []
    for element in case.findall("failure") + case.findall("error"):
        text = element.get("message") or element.text or ""
        lines += [line for line in text.splitlines() if line.strip()]
    shown = ["    " + line for line in lines[:max_lines]]
    if len(lines) > max_lines:
        shown.append("    ... (%d more lines)" % (len(lines) - max_lines))
    return shown


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results_dir", nargs="?",
                        default=os.path.join(os.path.dirname(here), "build", "test_results"))
    parser.add_argument("--write", metavar="FILE", help="also write the summary line to FILE")
    args = parser.parse_args(argv)

    if os.path.isdir(args.results_dir):
        counts, failures = summarise(args.results_dir)
    else:
        counts, failures = {"passed": 0, "failed": 0, "skipped": 0}, []
        print("no test results directory: %s" % args.results_dir)

    for line in failures:
        print(line)
    if counts["passed"] + counts["failed"] == 0:
        print("no tests ran")
    line = "%d passed, %d failed, %d skipped" % (counts["passed"], counts["failed"],
                                                  counts["skipped"])
    if args.write:
        with open(args.write, "w") as out:
            out.write(line + "\n")
    sys.stdout.flush()
    print(line, flush=True)
    return 1 if counts["failed"] or counts["passed"] + counts["failed"] == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
