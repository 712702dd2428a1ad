"""JUnit XML result files for the workspace checks (scripts/check_deps.py,
scripts/check_param_docs.py, scripts/test_install_space.py) and the scripts' unit tests, so that
scripts/test_summary.py counts them with the gtests."""
import argparse
import os
import time
import unittest
from xml.sax.saxutils import escape, quoteattr


def write_junit(path, suite, cases):
    """cases: (name, seconds, failure text or None, detail text) per test case."""
    failures = sum(1 for case in cases if case[2] is not None)
    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             '<testsuite name=%s tests="%d" failures="%d" errors="0">'
             % (quoteattr(suite), len(cases), failures)]
    for name, seconds, failure, detail in cases:
        lines.append('  <testcase classname=%s name=%s time="%.1f">'
                     % (quoteattr(suite), quoteattr(name), seconds))
        if failure is not None:
            lines.append("    <failure message=%s>%s</failure>"
                         % (quoteattr(failure.splitlines()[0] if failure else "failed"),
                            escape(failure)))
        elif detail:
            lines.append("    <system-out>%s</system-out>" % escape(detail))
        lines.append("  </testcase>")
    lines.append("</testsuite>")
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


def run_unit_tests(module, suite, description):
    """Runs the unittest cases of module (a test script's __main__) with a `--junit FILE` option
    that also writes them as JUnit suite `suite`; returns the exit status."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--junit", metavar="FILE", help="also write a JUnit XML result file")
    args = parser.parse_args()
    cases = []

    class Recorder(unittest.TextTestResult):
        def startTest(self, test):
            self.started = time.monotonic()
            super().startTest(test)

        def record(self, test, failure):
            cases.append((test.id().split(".", 1)[1], time.monotonic() - self.started, failure,
                          ""))

        def addSuccess(self, test):
            super().addSuccess(test)
            self.record(test, None)

        def addFailure(self, test, err):
            super().addFailure(test, err)
            self.record(test, self._exc_info_to_string(err, test))

        def addError(self, test, err):
            super().addError(test, err)
            self.record(test, self._exc_info_to_string(err, test))

    tests = unittest.defaultTestLoader.loadTestsFromModule(module)
    result = unittest.TextTestRunner(resultclass=Recorder, verbosity=2).run(tests)
    if args.junit:
        write_junit(args.junit, suite, cases)
    return 0 if result.wasSuccessful() else 1
