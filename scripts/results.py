#!/usr/bin/python3
"""Regenerates docs/RESULTS.md (`make results`): every table of figures is produced here by the
command that measures it, and the page names the date, the commit, the machine and, per table,
the command and its wall time.

    scripts/results.py [--quick] [--only NAME ...] [--output docs/RESULTS.md]

The tools run from the devel space (build/devel, `make build` first). Their outputs go to
build/results/; the pictures the tools draw go to docs/calibration/ and docs/images/. Fits of
evaluate_gait_id are cached in build/results/fit_cache (a re-run reuses them; delete the folder to
measure from scratch). --quick (RESULTS_QUICK=1) runs smaller sizes, stated in each table.
"""
import argparse
import datetime
import json
import os
import pathlib
import platform
import shlex
import subprocess
import sys
import time

import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent
WORK = pathlib.Path("build/results")
LIB = "build/devel/lib"
CONFIG = "body_scan_driver/config"
CACHE = WORK / "fit_cache"
CMU_MODELS = WORK / "cmu_walk_models"  # the CMU walks' walk-level fits (body_fit writes them)
CMU = "body_scan_driver/data/cmu_walks"
CMU_WALKS = ",".join(f"{CMU}/{w}.bvh" for w in ("07_02", "07_08", "08_03", "08_08", "35_01",
                                                "35_02"))


def ros_environment():
    """The environment of a shell that sourced the devel space (the tools find their data
    through the ROS package path)."""
    setup = ROOT / "build/devel/setup.bash"
    if not setup.exists():
        sys.exit("error: build/devel/setup.bash not found: run 'make build' first")
    out = subprocess.run(["bash", "-c", f"source {shlex.quote(str(setup))} && env -0"],
                         check=True, capture_output=True, cwd=ROOT).stdout
    env = dict(item.split("=", 1) for item in out.decode().split("\0") if "=" in item)
    env["PATH"] = "/usr/bin:" + env.get("PATH", "")
    return env


class Runner:
    def __init__(self, env):
        self.env = env
        self.log = open(ROOT / WORK / "results.log", "a")

    def run(self, command, output=None, extra_env=None):
        """Runs one shell command from the repository root; returns (stdout+stderr text, wall
        seconds). A failing command raises with the end of its output."""
        env = dict(self.env, **(extra_env or {}))
        self.log.write(f"\n== {command}\n")
        self.log.flush()
        start = time.monotonic()
        proc = subprocess.run(["bash", "-c", command], cwd=ROOT, env=env, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        seconds = time.monotonic() - start
        self.log.write(proc.stdout)
        self.log.flush()
        if output:
            (ROOT / output).write_text(proc.stdout)
        if proc.returncode != 0:
            tail = "\n".join(proc.stdout.splitlines()[-15:])
            raise RuntimeError(f"'{command}' exited with {proc.returncode}:\n{tail}")
        return proc.stdout, seconds


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return lines


def figure_lines(text):
    return [line.split("[ figure ]", 1)[1].strip() for line in text.splitlines()
            if "[ figure ]" in line]


def pct(x, digits=1):
    return f"{100 * x:.{digits}f} %"


# ---------------------------------------------------------------------------------------------
# Tables. Each returns (commands, markdown lines); `r` is the Runner, `q` the quick flag.

def t_test_figures(r, q, tests, what):
    commands, rows, seconds = [], [], 0.0
    for package, test in tests:
        command = f"{LIB}/{package}/{test}"
        text, s = r.run(command)
        seconds += s
        commands.append(command)
        rows += [(f"`{test}`", line.replace("|", "\\|")) for line in figure_lines(text)]
    return commands, seconds, [f"What the unit tests measure against ground truth or a named "
                               f"peer ({what}; the lines tagged `[ figure ]` in their output):",
                               ""] + table(["test", "figure"], rows)


def range_sensing(r, q):
    return t_test_figures(r, q, [("body_scan_driver", "test_stripe_decoder"),
                                 ("body_scan_driver", "test_triangulation")],
                          "one simulated pair, 640x480, 8-bit Gray code")


def camera_calibration(r, q):
    return t_test_figures(r, q, [("body_scan_calib", "test_camera_calibration_images")],
                          "OpenCV's sample chessboard images and boards rendered by the "
                          "virtual pair")


def pair_calibration(r, q):
    exposures = 4 if q else 16
    command = (f"{LIB}/body_scan_calib/calibrate_simulated_pair --exposures {exposures} "
               f"--output docs/calibration/pair.yaml --report docs/calibration/pair_accuracy.yaml "
               f"--plot docs/calibration/projector_parameters.png")
    _, seconds = r.run(command)
    report = yaml.safe_load((ROOT / "docs/calibration/pair_accuracy.yaml").read_text())
    camera, projector = report["camera"], report["projector"]
    lines = [f"Simulated pair (pole_a/pair_1) with the optics of real captures (SIMULATOR.md) "
             f"and their robust decoding, reference board in "
             f"{camera['reference_plane_poses']} poses, {exposures} exposures "
             f"averaged per pattern; sphere accuracy E_s (thesis eq 3.31, Table 3.2 layout) of the "
             f"plane-per-stripe model against the pinhole-projector baseline. Plot: "
             f"`docs/calibration/projector_parameters.png`.", ""]
    for block in report["sphere_accuracy_eq_3_31"]:
        n = block["exposures_averaged_per_pattern"]
        lines += [f"Spheres r = {block['radius_mm']} mm, {n} exposure(s) per pattern:", ""]
        header = ["sphere"] + [f"No. {i}" for i in block["sphere_number"]] + ["mean"]
        rows = [
            ["points"] + block["measuring_points_plane_model"] + [""],
            ["E_s pinhole projector [mm^2]"] + block["e_s_mm2_approach_i_pinhole_projector"]
            + [block["mean_e_s_mm2_pinhole_projector"]],
            ["E_s plane per stripe [mm^2]"] + block["e_s_mm2_approach_iii_plane_per_stripe"]
            + [block["mean_e_s_mm2_plane_per_stripe"]],
            ["improvement %"] + block["improvement_percent"] + [block["mean_improvement_percent"]],
            ["centre error pinhole / plane [mm]"]
            + [f"{a} / {b}" for a, b in zip(block["center_error_mm_pinhole_projector"],
                                            block["center_error_mm_plane_per_stripe"])] + [""],
        ]
        lines += table(header, rows) + [""]
    a = camera["alpha_beta_gamma_u0_v0"]
    lines += [f"Camera: fx {a[0]}, fy {a[1]}, cx {a[3]}, cy {a[4]} (true 810, 810, 319.5, "
              f"239.5), reprojection RMS {camera['reprojection_rms_px']} px. Projector: "
              f"{projector['planes_fitted']} of {projector['stripes']} planes (stripes seen on "
              f"fewer than 3 poses are NaN), plane-fit RMS {projector['plane_fit_rms_mm']} mm."]
    return [command], seconds, lines


def world_alignment(r, q):
    exposures = 2 if q else 16
    command = (f"EXPOSURES={exposures} REPORT=docs/calibration/world_alignment.yaml "
               f"PLOT=docs/calibration/world_alignment.png scripts/calibrate_simulated_rig.sh "
               f"{WORK}/simulated_rig")
    _, seconds = r.run(command)
    report = yaml.safe_load((ROOT / "docs/calibration/world_alignment.yaml").read_text())
    rows = []
    for pair in report["pairs"]:
        check = pair.get("simulator_check", {})
        rows.append([pair["pair_id"], pair.get("markers", ""), pair.get("grid_points_detected", ""),
                     pair.get("grid_points_triangulated", ""), pair.get("fit_rms_mm", ""),
                     check.get("rotation_error_deg", ""), check.get("translation_error_mm", "")])
    e = report["E_h"]
    lines = [f"The simulated 2x2 alignment rig (optics of real captures) calibrated from "
             f"observations only (each pair "
             f"from the board and spheres, {exposures} exposures per pattern, then aligned on "
             f"the calibration cylinder with those estimated files). Report and plot: "
             f"`docs/calibration/world_alignment.yaml`, `.png`.", ""]
    lines += table(["pair", "markers", "grid points detected", "triangulated",
                    "affine fit RMS mm", "rotation vs truth deg", "translation vs truth mm"], rows)
    lines += ["", f"**E_h (eq 4.2, Table 4.2): {e['shared_points']} shared points "
                  f"({e['comparisons']} comparisons), mean {e['mean_mm']} mm, std {e['std_mm']} mm, "
                  f"max {e['max_mm']} mm** (thesis: 33 points, mean 1.88 mm, std 0.79 mm)."]
    return [command], seconds, lines


def real_captures(r, q):
    return t_test_figures(r, q, [("body_scan_calib", "test_real_captures"),
                                 ("body_scan_calib", "test_pattern_contrast")],
                          "a trimmed public real capture set, OpenCV layout, "
                          "`body_scan_calib/test/data/kamino_procam`; leave-one-pose-out "
                          "validation against the OpenCV pinhole-projector calibration")


def whole_body(r, q):
    scenes = [("standing_person", "planned", "standing, planned groups"),
              ("walking_person", "planned", "walking (gait pose 1), planned groups")]
    if not q:
        scenes += [("standing_person", "all", "standing, all 12 pairs at once (interference)"),
                   ("mesh_person", "planned", "mesh human standing, planned groups")]
    commands, rows, seconds = [], [], 0.0
    for scene, groups, label in scenes:
        cloud = WORK / f"scan_{scene}_{groups}.ply"
        report = WORK / f"scan_{scene}_{groups}.yaml"
        scan = (f"{LIB}/body_scan_merge/simulate_scan --rig {CONFIG}/rigs/thesis_rig.yaml "
                f"--scene {CONFIG}/scenes/{scene}.yaml --groups {groups} --output {cloud}")
        evaluate = (f"{LIB}/body_scan_merge/evaluate_scan --cloud {cloud} "
                    f"--scene {CONFIG}/scenes/{scene}.yaml --report {report}")
        _, s1 = r.run(scan)
        _, s2 = r.run(evaluate)
        seconds += s1 + s2
        commands += [scan, evaluate]
        a = yaml.safe_load((ROOT / report).read_text())
        reg = a["coverage"]["regions"]
        rows.append([label, f"{a['points']:,}".replace(",", " "),
                     f"{a['distance_mm']['mean']:.3g} / {a['distance_mm']['p95']:.3g} mm",
                     a["outliers"], pct(a["coverage"]["body_without_soles"]),
                     pct(reg["under_chin"]["fraction"]),
                     f"{pct(reg['armpit_left']['fraction'])} / {pct(reg['armpit_right']['fraction'])}",
                     pct(reg["groin"]["fraction"]),
                     f"{pct(reg['torso_side_left']['fraction'])} / "
                     f"{pct(reg['torso_side_right']['fraction'])}", f"{s1:.0f} s"])
    lines = ["The 12-pair scanner (thesis rig: 3 poles x 4 pairs) simulated at core level "
             "(`simulate_scan`: render by timing group, decode, triangulate, merge with the Merge "
             "nodelet's code, 1.5 mm voxel grid), then compared with the true surface "
             "(`evaluate_scan`: mean and 95th percentile point-to-surface distance, points beyond "
             "20 mm, share of the body's area with a point within 5 mm). Targets: mean <= 2 mm, "
             "coverage >= 95 %, each hard region >= 80 %.", ""]
    lines += table(["scene, groups", "points", "mean / p95", "outliers > 20 mm", "coverage",
                    "under chin", "armpits L / R", "groin", "torso sides L / R",
                    "scan wall time"], rows)
    return commands, seconds, lines


def interference(r, q):
    return t_test_figures(r, q, [("body_scan_driver", "test_rig")],
                          "wrong stripes on the person when the other pairs project at the "
                          "same time; the timing groups keep them apart")


def fit_row(label, summary):
    s = summary
    return [label, s["fits"], f"{1000 * s['mean_joint_error_m']:.1f} mm",
            f"{1000 * s['procrustes_joint_error_m']:.1f} mm",
            f"{1000 * s['offset_removed_joint_error_m']:.1f} mm", pct(s["mean_length_error"]),
            f"{s['mean_swing_error_rad'] * 57.29578:.2f} deg",
            f"{s['heading_right']}/{s['fits']}", s["low_quality"],
            "{}/{}, {}/{}".format(*s["flag_precision"], *s["flag_recall"]),
            f"{1000 * s['mean_fit_seconds']:.0f} ms"]


FIT_HEADER = ["case", "fits", "joint centre error", "Procrustes", "offsets removed",
              "segment length error",
              "swing angle error", "facing right", "flagged low quality",
              "flag precision, recall (> 50 mm)", "time per fit"]


def body_fit(r, q):
    subjects = 3 if q else 10
    full = 2 if q else 10  # the full scanner's cases: about 3 s a scan
    cases = [
        (f"sampler (ray cast from the 12 viewpoints, 2 mm noise), {subjects} subjects x 4 poses",
         f"--subjects {subjects} --columns 300", "sampler"),
        ("sampler, a whole pole missing", f"--subjects {subjects} --columns 300 "
         f"--missing-viewpoints 4,5,6,7", "sampler_pole_missing"),
        (f"full scanner simulation, {full} subjects x 4 poses, walk-level fit",
         f"--full-scanner --subjects {full} --fit walk", "full_walk"),
        ("the same, every scan fitted alone", f"--full-scanner --subjects {full} --fit scan",
         "full_scan"),
        (f"mesh human (`--body mesh`), sampler, {subjects} subjects x 4 poses",
         f"--subjects {subjects} --columns 300 --body mesh", "mesh_sampler"),
        (f"mesh human, full scanner simulation, {full} subjects x 4 poses, walk-level fit",
         f"--full-scanner --subjects {full} --fit walk --body mesh",
         "mesh_full_walk"),
    ]
    if not q:
        cases += [
            ("CMU motion-capture walks (6 walks x 4 poses), full scanner, walk-level fit",
             f"--bvh {CMU_WALKS} --fit walk --models {CMU_MODELS}", "cmu_walk"),
            ("the same, every scan fitted alone", f"--bvh {CMU_WALKS} --fit scan", "cmu_scan"),
            ("CMU walks on the mesh human, full scanner, walk-level fit",
             f"--bvh {CMU_WALKS} --fit walk --body mesh", "cmu_mesh_walk"),
        ]
    commands, rows, seconds = [], [], 0.0
    for label, args, name in cases:
        out = WORK / f"body_fit_{name}.yaml"
        command = f"{LIB}/body_gait_model/evaluate_body_fit {args} --out {out}"
        _, s = r.run(command)
        seconds += s
        commands.append(command)
        rows.append(fit_row(label, yaml.safe_load((ROOT / out).read_text())["summary"]))
    lines = ["The 12-segment body model (thesis 5.4-5.5) fitted to simulated subjects in the four "
             "gait poses of thesis 5.3 (or to motion-capture walks) and compared with the true "
             "skeleton. Targets: joint centre error <= 25 mm, segment length <= 5 %, swing angle "
             "<= 4 deg, every fit facing right, none flagged. The flag's precision and recall are "
             "for fits whose mean joint error exceeds 50 mm (flagged bad / flagged, flagged "
             "bad / bad). \"Offsets removed\": the joint "
             "error once each joint's mean offset (fitted - true, in the body frame), learned on "
             "the other people's fits, is subtracted; what is left is the fits' scatter, without "
             "the difference between where the fitter and the truth put a joint (a straight "
             "elbow's or knee's standard proportion, which the CMU and MakeHuman skeletons do not "
             "share).", ""]
    return commands, seconds, lines + table(FIT_HEADER, rows)


def gait_rows(report, names=None):
    rows = []
    for res in report["results"]:
        if names and res["name"] not in names:
            continue
        ir = res.get("identification_rate")
        if not ir:
            continue
        ci = ir.get("ci95", ["", ""])
        ver = res.get("verification", {})
        eer = ver.get("equal_error_rate")
        thesis = res.get("thesis", {})
        rows.append([res["name"], f"{100 * ir['rate']:.2f} [{100 * ci[0]:.1f}, {100 * ci[1]:.1f}]",
                     ir["n"],
                     f"{res.get('average_pose_error_frames', float('nan')):.2f} / "
                     f"{res.get('average_cyclic_pose_error_frames', float('nan')):.2f}",
                     "" if eer is None else f"{100 * eer:.2f}",
                     "" if ver.get("eer_threshold") is None else f"{ver['eer_threshold']:.2f}",
                     thesis.get("identification_rate_percent", "-")])
    return rows


GAIT_HEADER = ["features", "rank-1 % (95 % CI)", "probes", "pose error plain / cyclic (frames)",
               "EER %", "EER threshold", "thesis rank-1 %"]


def recognition_thesis(r, q):
    subjects = 6
    scanner = "sampler" if q else "full"
    commands, seconds, lines = [], 0.0, []
    for body in ("ellipsoid", "mesh"):
        report = WORK / f"gait_id_thesis{'_mesh' if body == 'mesh' else ''}.yaml"
        command = (f"{LIB}/body_gait_id/evaluate_gait_id --protocol thesis --subjects {subjects} "
                   f"--scanner {scanner} --transform lda --cache {CACHE} --quiet "
                   f"--report {report}" + (" --body mesh" if body == "mesh" else
                                          f" --plot {WORK}/gait_id_thesis.png"))
        text, s = r.run(command)
        seconds += s
        commands.append(command)
        lines += [f"Thesis protocol (5.8.3): {subjects} simulated people "
                  f"({'the mesh human' if body == 'mesh' else 'ellipsoid bodies'}), {scanner} "
                  f"scanner; gallery eta1 + eta2 of walk 0, probes the 16 interpolated frames of "
                  f"eta3. {first_line(text)}", ""]
        lines += table(GAIT_HEADER, gait_rows(load(report))) + [""]
    return commands, seconds, lines[:-1]


def first_line(text):
    for line in text.splitlines():
        if " protocol, " in line and " scans " in line:
            return line.strip() + "."
    return ""


def load(path):
    return yaml.safe_load((ROOT / path).read_text())


def noise_source(name):
    """What a shipped noise file was learned on: its own `source:` line."""
    path = ROOT / "body_gait_id/config" / name
    return f"`{name}`, learned on: {yaml.safe_load(path.read_text())['source']}"


def recognition_cross_walk(r, q):
    subjects = 20 if q else 50
    plot = "docs/images/gait_id_cross_walk_weighted.png"
    commands, seconds, lines = [], 0.0, []
    for body in ("ellipsoid", "mesh"):
        report = WORK / f"gait_id_cross_walk{'_mesh' if body == 'mesh' else ''}.yaml"
        command = (f"{LIB}/body_gait_id/evaluate_gait_id --protocol cross-walk "
                   f"--subjects {subjects} --scanner sampler --rows 3d --per-walk --shape "
                   "--walk-body median --noise-file body_gait_id/config/feature_noise_sampler.yaml "
                   f"--cache {CACHE} --quiet --report {report}"
                   + (" --body mesh" if body == "mesh" else f" --plot {plot}"))
        text, s = r.run(command)
        seconds += s
        commands.append(command)
        lines += [f"Cross-walk (gallery walk 0, probes all 20 frames of eta3 of walk 1; per walk: "
                  f"one decision per probe walk), {subjects} simulated people "
                  f"({'the mesh human' if body == 'mesh' else 'ellipsoid bodies'}), sampler "
                  f"scanner, 3D features; the shipped noise weights "
                  f"({noise_source('feature_noise_sampler.yaml')}), median walk body. "
                  f"{first_line(text)}"
                  + ("" if body == "mesh" else f" Plot: `{plot}`."), ""]
        lines += table(GAIT_HEADER, gait_rows(load(report)))
        open_set = [line.strip() for line in text.splitlines() if "FNIR" in line or "FPIR" in line]
        if open_set:
            lines += ["", "Open set (half of the people enrolled, the others strangers):", "",
                      "```"] + open_set + ["```"]
        lines += [""]
    return commands, seconds, lines[:-1]


def benchmarks(r, q):
    min_time = "0.05" if q else "0.1"
    runs = [
        ("body_scan_driver", "bench_decode_triangulate", ""),
        ("body_scan_merge", "bench_full_scan", ""),
        ("body_gait_model", "bench_body_fit", ""),
        ("body_gait_model", "bench_full_scanner_sim", ""),
        ("body_gait_id", "bench_identify", "--benchmark_filter='/(10000|100000)/'"),
    ]
    commands, seconds, jsons = [], 0.0, []
    bench_dir = WORK / "bench"
    (ROOT / bench_dir).mkdir(parents=True, exist_ok=True)
    for package, name, extra in runs:
        out = bench_dir / f"{name}.json"
        command = (f"{LIB}/{package}/{name} --benchmark_min_time={min_time} "
                   f"--benchmark_repetitions=3 --benchmark_out={out} "
                   f"--benchmark_out_format=json {extra}").strip()
        _, s = r.run(command)
        seconds += s
        commands.append(command)
        jsons.append(str(out))
    report_command = "scripts/bench_report.py " + " ".join(jsons[:-1])
    text, _ = r.run(report_command)
    commands.append(report_command)
    lines = ["Google Benchmark medians of 3 repetitions (CPU time; wall time for the "
             "multi-threaded cases, or the whole process's CPU time where marked), and every "
             "peer's time over ours in the same run "
             "(`scripts/bench_report.py`). Only the in-run ratios compare across machines.", "",
             "```"] + text.rstrip().splitlines() + ["```", ""]
    lines += ["Identification latency (`bench_identify`: synthetic people who walk alike, 40 "
              "gallery poses each; genuine probes are enrolled people at new phases, impostors "
              "people not enrolled), CPU time per query, the indexed matcher against the "
              "brute-force double peer (galleries of 1 000 000 poses are not run here):", ""]
    lines += table(["gallery poses", "features", "indexed, genuine",
                    "brute force, genuine (brute / indexed)", "indexed, impostor",
                    "brute force, impostor (brute / indexed)"], identify_rows(ROOT / jsons[-1]))
    return commands, seconds, lines


def identify_rows(path):
    medians = {}
    for b in json.loads(path.read_text())["benchmarks"]:
        if b.get("aggregate_name") == "median":
            name, poses, features = b["run_name"].split("/")[:3]
            medians[(name, int(poses), int(features))] = b["cpu_time"]
    features = {0: "dynamic (22-D)", 1: "dynamic + static (34-D)", 2: "+ body shape (58-D)"}
    rows = []
    for poses, set_ in sorted({(k[1], k[2]) for k in medians}, key=lambda k: (k[1], k[0])):
        def cell(kind):
            ours = medians.get((f"indexed{kind}", poses, set_))
            peer = medians.get((f"bruteDouble{kind}", poses, set_))
            if ours is None or peer is None:
                return "", ""
            return f"{ours:.1f} us", f"{peer:.1f} us ({peer / ours:.1f}x)"
        g, gp = cell("Genuine")
        i, ip = cell("Impostor")
        rows.append([f"{poses:,}".replace(",", " "), features.get(set_, set_), g, gp, i, ip])
    return rows


def recognition_full_scanner(r, q):
    subjects = 4 if q else 10
    report = WORK / "gait_id_full_walks.yaml"
    scans_report = WORK / "gait_id_full_scans.yaml"
    base = (f"{LIB}/body_gait_id/evaluate_gait_id --protocol cross-walk --subjects {subjects} "
            f"--scanner full --rows 3d --shape --walk-body median "
            f"--noise-file body_gait_id/config/feature_noise_full_scanner.yaml --cache {CACHE} "
            f"--quiet")
    walks = f"{base} --per-walk --report {report} --plot docs/images/gait_id_cross_walk_full.png"
    scans = f"{base} --probe-frames scans --report {scans_report}"
    text, s1 = r.run(walks)
    _, s2 = r.run(scans)
    wanted = {"3D dynamic+static+shape weighted", "3D dynamic+static+shape weighted per walk",
              "3D dynamic+static", "3D dynamic+static per walk"}
    rows = gait_rows(load(report), wanted)
    rows += gait_rows(load(scans_report), {"3D dynamic+static single scans",
                                           "3D dynamic+static+shape weighted single scans"})
    lines = [f"Cross-walk on the 12-pair scanner simulation with the product's recognition "
             f"settings (`recognition.launch`: body shape, median walk body, the full scanner's "
             f"noise file, {noise_source('feature_noise_full_scanner.yaml')}: other people "
             f"than these {subjects}). Rows: per frame of the probe walk's cycle, per "
             f"walk, and walk 1's four fits as single-scan probes (how `gait_id_node` identifies "
             f"each scan of a walk; its "
             f"EER threshold is what `accept_threshold` should be). {first_line(text)} Plot: "
             f"`docs/images/gait_id_cross_walk_full.png`.", ""]
    return [walks, scans], s1 + s2, lines + table(GAIT_HEADER, rows)


def recognition_full_scanner_mesh(r, q):
    subjects = 10 if q else 50
    commands, seconds, lines = [], 0.0, []
    # The thresholds were chosen on seed 1 and the noise file learned on seed 2; nothing the
    # full scanner uses comes from seed 3, so its figures tell how far those carry to new people.
    for seed in (1, 3):
        report = WORK / f"gait_id_full_mesh_walks{'' if seed == 1 else f'_seed{seed}'}.yaml"
        command = (f"{LIB}/body_gait_id/evaluate_gait_id --protocol cross-walk "
                   f"--subjects {subjects} --seed {seed} --scanner full --body mesh --rows 3d "
                   f"--decomposition --per-walk --walk-body median "
                   f"--noise-file body_gait_id/config/feature_noise_full_scanner.yaml "
                   f"--cache {CACHE} --quiet --report {report}")
        text, took = r.run(command)
        commands.append(command)
        seconds += took
        rows = [row for row in gait_rows(load(report)) if row[0].endswith("weighted per walk")]
        open_set = [line.strip() for line in text.splitlines()
                    if "weighted per walk" in line and "FNIR" in line]
        if seed == 1:
            lines += [f"Walk-level cross-walk of {subjects} simulated people (seed 1) with the "
                      f"mesh human's bodies on the 12-pair scanner simulation, product settings "
                      f"(median walk body, the full scanner's noise file, "
                      f"{noise_source('feature_noise_full_scanner.yaml')}: other people than "
                      f"these), one decision per walk; each feature alone and combined, so that "
                      f"a reader sees how much is gait (dynamic: joint angles) and how much body "
                      f"size (static: segment lengths; shape: radii, widths, height). "
                      f"{first_line(text)}", ""]
        else:
            lines += ["", f"The same for {subjects} other people (seed {seed}), on whom none of "
                      f"these settings was learned or chosen (the noise file was learned on seed "
                      f"2, the thresholds chosen on seed 1): how far the figures carry to new "
                      f"people. {first_line(text)}", ""]
        lines += table(GAIT_HEADER, rows)
        lines += ["", "Open set (half of the people enrolled, the others strangers):", "", "```"]
        lines += open_set + ["```"]
    return commands, seconds, lines


def recognition_cmu(r, q):
    if q:
        return [], 0.0, ["Skipped in quick mode (the CMU walks' scans take minutes)."]
    if not list((ROOT / CMU_MODELS).glob("[0-9]*.yaml")):
        raise RuntimeError(f"no CMU walk fits in {CMU_MODELS}: the body_fit table writes them; "
                           f"run it first (--only body_fit recognition_cmu)")
    report = WORK / "gait_id_cmu_walks.yaml"
    evaluate = (f"{LIB}/body_gait_id/evaluate_gait_id --protocol cross-walk --bvh {CMU_WALKS} "
                f"--scanner full --rows 3d --decomposition --per-walk --walk-body median "
                f"--noise-file body_gait_id/config/feature_noise_full_scanner.yaml "
                f"--cache {CACHE} --quiet --report {report}")
    text, s1 = r.run(evaluate)
    identify = f"{LIB}/body_gait_id/identify_walks {CMU_MODELS}/[0-9]*.yaml"
    votes, s2 = r.run(identify)
    rows = [row for row in gait_rows(load(report)) if row[0].endswith("per walk")]
    lines = [f"The six CMU walks (3 people x 2 walks, motion capture driving the ellipsoid body) "
             f"scanned by the full scanner and fitted walk by walk. `evaluate_gait_id --bvh`: "
             f"gallery walk 0 of each person, probe walk 1, one decision per walk, product "
             f"settings. {first_line(text)}", ""]
    lines += table(GAIT_HEADER, rows)
    lines += ["", "`identify_walks` on the body-fit table's CMU fits (`--models`): each walk "
              "identified against the other walk of every person, the 20 frames of its cycle "
              "voting:", "", "```"]
    lines += [line.rstrip() for line in votes.splitlines() if "walks identified by vote" in line]
    lines += ["```"]
    return [evaluate, identify], s1 + s2, lines


NOT_COVERED = [
    "identification latency at 1 000 000 gallery poses (`bench_identify` without the filter)",
    "cross-walk recognition of 50 ellipsoid-body people on the full scanner, LDA, two-walk "
    "enrolment and the robust distance (`evaluate_gait_id --transform lda`, `--gallery-walks 2`, "
    "`--robust-sigmas 3`; EVALUATION.md)",
    "the full scanner's robustness cases (`evaluate_body_fit --full-scanner --abduction-deg 0`, "
    "`--dark-albedo 0.03`, `--missing-pairs`)",
    "system runs: `make soak`, `scripts/distributed_poles.py` (needs root), `make fuzz`",
    "pictures that need a display (the rviz screenshots) or a run of their own (the fitted "
    "walk strip `docs/images/bvh_07_02_scanned_poses.png`, the mesh walker)",
]


SECTIONS = [
    ("Range sensing", [("range_sensing", "Decoding and triangulation (one pair)", range_sensing)]),
    ("Calibration", [
        ("camera_calibration", "Camera calibration", camera_calibration),
        ("pair_calibration", "Pair calibration: plane per stripe vs pinhole projector",
         pair_calibration),
        ("world_alignment", "World alignment on the calibration cylinder", world_alignment),
        ("real_captures", "Real captures (public data set)", real_captures),
    ]),
    ("Whole body", [
        ("whole_body", "Whole-body scan accuracy and coverage", whole_body),
        ("interference", "Interference between pairs", interference),
    ]),
    ("Body fit", [("body_fit", "Body model fit against the true skeleton", body_fit)]),
    ("Recognition", [
        ("recognition_thesis", "Thesis protocol", recognition_thesis),
        ("recognition_cross_walk", "Cross-walk identification", recognition_cross_walk),
        ("recognition_full_scanner", "Cross-walk on the full scanner, product settings",
         recognition_full_scanner),
        ("recognition_full_scanner_mesh", "Walks of mesh people on the full scanner: gait against "
         "body size", recognition_full_scanner_mesh),
        ("recognition_cmu", "CMU motion-capture walks", recognition_cmu),
    ]),
    ("Benchmarks", [("benchmarks", "Speed against named peers", benchmarks)]),
]


def machine():
    model = "unknown CPU"
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            model = line.split(":", 1)[1].strip()
            break
    return f"{os.cpu_count()} cores, {model}, {platform.system()} {platform.release()}"


def commit():
    head = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT, text=True,
                          capture_output=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                           text=True, capture_output=True).stdout.strip()
    return head + (" (with uncommitted changes)" if dirty else "")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", default=bool(os.environ.get(
        "RESULTS_QUICK")), help="smaller sizes (also RESULTS_QUICK=1)")
    parser.add_argument("--only", nargs="*", help="table names to run (others are left out)")
    parser.add_argument("--output", default="docs/RESULTS.md")
    args = parser.parse_args()

    (ROOT / WORK).mkdir(parents=True, exist_ok=True)
    runner = Runner(ros_environment())
    started = datetime.datetime.now(datetime.timezone.utc)
    measured_commit = commit()
    load_start = os.getloadavg()[0]
    cached_fits = len(list((ROOT / CACHE).glob("*"))) if (ROOT / CACHE).is_dir() else 0
    t0 = time.monotonic()
    body, failures = [], []
    for section, tables in SECTIONS:
        body += [f"## {section}", ""]
        for name, title, fn in tables:
            if args.only and name not in args.only:
                continue
            print(f"== {name}", flush=True)
            body += [f"### {title}", ""]
            try:
                commands, seconds, lines = fn(runner, args.quick)
                body += lines + ["", f"Measured by ({seconds:.0f} s):", "", "```"]
                body += commands + ["```", ""]
                print(f"   {seconds:.0f} s", flush=True)
            except Exception as error:  # one failing table does not lose the others
                failures.append(name)
                body += ["**Not measured in this run**: the command failed:", "", "```",
                         str(error), "```", ""]
                print(f"   FAILED: {error}", file=sys.stderr, flush=True)
    total = time.monotonic() - t0
    mode = ("quick (`RESULTS_QUICK=1`: smaller sizes, stated per table)" if args.quick else
            "full")
    head = [
        "# Results",
        "",
        "Generated by `make results` (`scripts/results.py`); do not edit by hand. Every table "
        "below is produced by the command printed under it, run from the repository root after "
        "`make build`.",
        "",
        f"* Date: {started:%Y-%m-%d %H:%M} UTC; run time {total / 60:.1f} min; mode: {mode}",
        f"* Commit: {measured_commit}",
        f"* Machine: {machine()}; load average {load_start:.1f} at the start, "
        f"{os.getloadavg()[0]:.1f} at the end (absolute times vary with the load; the "
        "benchmarks' in-run ratios much less)",
        f"* Caches: evaluate_gait_id's fits in `{CACHE}`, {cached_fits} entries at the start "
        "(later tables reuse the fits of earlier ones; a re-run skips the scans and fits, delete "
        "the folder to measure from scratch); everything else is measured afresh",
        "",
        "Sections: " + ", ".join(f"[{s}](#{s.lower().replace(' ', '-')})" for s, _ in SECTIONS),
        "",
    ]
    head += ["Not covered by `make results` yet (each has its command in "
             "[EVALUATION.md](EVALUATION.md)):", ""] + [f"* {item}" for item in NOT_COVERED] + [""]
    if failures:
        head += [f"Tables not measured in this run: {', '.join(failures)}.", ""]
    (ROOT / args.output).write_text("\n".join(head + body).rstrip() + "\n")
    print(f"wrote {args.output} in {total / 60:.1f} min"
          + (f"; failed: {', '.join(failures)}" if failures else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
