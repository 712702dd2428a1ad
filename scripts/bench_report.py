#!/usr/bin/python3
"""Ratios from Google Benchmark JSON: within each group ".../name", every peer's time over the
group's ".../ours" (how many times longer the peer takes), and for the floors (".../copy",
".../read_frames_write_outputs") also ours over the floor (how many floors ours takes), plus the
absolute times. Cases run with repetitions are summarised by their median. Writes the report
next to the JSON files and prints it."""
import json
import pathlib
import sys

FLOORS = ("copy", "read_frames_write_outputs")


def base_name(name):
    """Benchmark name without Google Benchmark's suffixes (/real_time, /iterations:N, ...)."""
    parts = [p for p in name.split("/") if ":" not in p and p not in ("real_time", "process_time")
             and not p.isdigit()]
    return "/".join(parts)


def timings(results):
    """{base name: (time, unit, label)}: the median aggregate where there is one, else the
    single iteration run. Multi-threaded cases (names with /real_time) use the wall clock, or the
    whole process's CPU time where they measure it (/process_time; the wall clock in the label)."""
    times = {}
    for r in results:
        run_name = r.get("run_name", r["name"])
        is_median = r.get("run_type") == "aggregate" and r.get("aggregate_name") == "median"
        is_single = r.get("run_type", "iteration") == "iteration"
        if not (is_median or is_single):
            continue
        name = base_name(run_name)
        if is_single and name in times:
            continue  # a median of the same case wins over its repetitions
        time = r["real_time"] if "/real_time" in run_name else r["cpu_time"]
        label = r.get("label", "")
        if "/process_time" in run_name:  # the work on every thread: steadier on a shared machine
            time = r["cpu_time"]
            label = f"process CPU time (wall {r['real_time']:.3f} {r['time_unit']}) {label}"
        if is_median or name not in times:
            times[name] = (time, r["time_unit"], label)
    return times


def main(paths):
    lines = []
    for path in map(pathlib.Path, paths):
        times = timings(json.loads(path.read_text())["benchmarks"])
        lines.append(f"{path.stem} (medians):")
        for name, (time, unit, label) in times.items():
            lines.append(f"  {name:55s} {time:10.3f} {unit} {label}".rstrip())
        groups = {name.rsplit("/", 1)[0] for name in times if name.endswith("/ours")}
        for group in sorted(groups):
            ours = times[f"{group}/ours"][0]
            for name, (time, _, _) in times.items():
                if name.rsplit("/", 1)[0] == group and not name.endswith("/ours"):
                    peer = name.rsplit("/", 1)[1]
                    line = f"  {group}: {peer} / ours = {time / ours:.2f}"
                    if peer in FLOORS:
                        line += f"   (ours / {peer} = {ours / time:.2f})"
                    lines.append(line)
    report = "\n".join(lines)
    print(report)
    if paths:
        (pathlib.Path(paths[0]).parent / "report.txt").write_text(report + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
