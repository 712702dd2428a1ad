#!/usr/bin/python3
"""Ratios from Google Benchmark JSON: within each group "Group/name", every member's time over
the group's "ours" (how many times slower the peer is), plus the absolute times. Writes the
report next to the JSON files and prints it."""
import json
import pathlib
import sys


def main(paths):
    lines = []
    for path in map(pathlib.Path, paths):
        results = json.loads(path.read_text())["benchmarks"]
        # Multi-threaded benchmarks are timed on the wall clock (their names end in /real_time).
        times = {r["name"]: (r["real_time"] if r["name"].endswith("/real_time") else r["cpu_time"],
                             r["time_unit"]) for r in results
                 if r.get("run_type", "iteration") == "iteration"}
        lines.append(f"{path.stem}:")
        for name, (time, unit) in times.items():
            lines.append(f"  {name:45s} {time:10.3f} {unit}")
        groups = {name.split("/")[0] for name in times if "/" in name}
        for group in sorted(groups):
            ours = times.get(f"{group}/ours")
            if not ours:
                continue
            for name, (time, _) in times.items():
                if name.startswith(group + "/") and name != f"{group}/ours":
                    lines.append(f"  ratio {name} / ours = {time / ours[0]:.2f}")
    report = "\n".join(lines)
    print(report)
    if paths:
        (pathlib.Path(paths[0]).parent / "report.txt").write_text(report + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
