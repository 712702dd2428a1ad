"""JUnit XML result files for the workspace checks (scripts/check_deps.py,
scripts/check_param_docs.py, scripts/test_install_space.py), so that scripts/test_summary.py
counts them with the gtests."""
import os
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
