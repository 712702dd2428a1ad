#!/usr/bin/python3
"""Ratios from Google Benchmark JSON: within each group ".../name", every peer's time over the
group's ".../ours" (how many times longer the peer takes), plus the absolute times. Writes the
report next to the JSON files and prints it."""
import json
import pathlib
import sys


def base_name(name):
    """Benchmark name without Google Benchmark's suffixes (/real_time, /iterations:N, ...)."""
    parts = [p for p in name.split("/") if ":" not in p and p != "real_time"
             and not p.isdigit()]
    return "/".join(parts)


def main(paths):
    lines = []
    for path in map(pathlib.Path, paths):
        results = json.loads(path.read_text())["benchmarks"]
        # Multi-threaded benchmarks are timed on the wall clock (their names end in /real_time).
        times = {base_name(r["name"]): (r["real_time"] if r["name"].endswith("/real_time")
                                        else r["cpu_time"], r["time_unit"]) for r in results
                 if r.get("run_type", "iteration") == "iteration"}
        lines.append(f"{path.stem}:")
        for name, (time, unit) in times.items():
            lines.append(f"  {name:45s} {time:10.3f} {unit}")
        groups = {name.rsplit("/", 1)[0] for name in times if name.endswith("/ours")}
        for group in sorted(groups):
            ours = times[f"{group}/ours"][0]
            for name, (time, _) in times.items():
                if name.rsplit("/", 1)[0] == group and not name.endswith("/ours"):
                    peer = name.rsplit("/", 1)[1]
                    lines.append(f"  {group}: {peer} / ours = {time / ours:.2f}")
    report = "\n".join(lines)
    print(report)
    if paths:
        (pathlib.Path(paths[0]).parent / "report.txt").write_text(report + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
