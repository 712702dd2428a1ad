#!/usr/bin/env bash
# The main job (make demo): a gait gallery of 6 simulated people is enrolled from their walks
# (walk 0 of each: the 4 representative gait poses of thesis 5.3 scanned with the 12-pair
# simulation, fitted together as the live walk is, reconstructed to the eta1/eta2 training
# cycles), then one of them walks through the ROS pipeline on ANOTHER walk (person_003, walk 1):
# /body_scan/capture_walk scans
# the 4 poses in turn (a simulated subject takes each pose at the coordinator's prompt), the
# merged cloud of the first pose is written to build/demo/full_scan.ply and .pcd, its scan
# report is printed, the fitter fits the walk and gait_id_node identifies it: the walk-level
# answer and the single-scan answers of its 4 scans. Headless, own ROS master.
#   SCENE=path/to/scene.yaml scripts/demo.sh    (one scan of another scene; likely unknown)
#   DEMO_PERSON=0..5 scripts/demo.sh            (which enrolled person walks through; 6..: a
#                                                stranger)
#   DEMO_BODY=mesh scripts/demo.sh              (the people as the skinned mesh human instead of
#                                                ellipsoids: enrolled and scanned live)
#   LAUNCH_ARGS="outlier_removal:=true voxel_leaf:=0.002" scripts/demo.sh  (full_scanner args)
set -euo pipefail
export PATH=/usr/bin:$PATH
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
set +u
source "$root/build/devel/setup.bash"
set -u

port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI="http://localhost:$port"
export ROS_HOME="$root/build/ros_home"
demo="$root/build/demo"
person=${DEMO_PERSON:-3}
body=${DEMO_BODY:-ellipsoid}
mkdir -p "$demo" "$ROS_HOME"
rm -f "$demo/full_scan.ply" "$demo/full_scan.pcd" "$demo/identity.txt"

gallery="$demo/gait_gallery.db"
rm -f "$gallery" "$gallery-wal" "$gallery-shm"
scene_args=(--scene-out "$demo/scene.yaml" --scene-person "$person" --scene-trial 1 --scene-pose 1
  --walk-scenes "$demo/walk")
walk_args=(walk_scenes:="$demo/walk")
[ -n "${SCENE:-}" ] && scene_args=() && walk_args=()
echo "== enrolling 6 simulated people in $gallery from their walks: walk 0 of each, its 4 poses"
echo "   scanned with the 12-pair simulation and fitted together, as the live walk is (cached in"
echo "   $demo/fit_cache: a re-run takes seconds); body: $body"
rosrun body_gait_id enroll_simulated_people --database "$gallery" --people 6 --body "$body" \
  --cache "$demo/fit_cache" "${scene_args[@]}" 2> "$demo/enroll.log" ||
  { tail -n 20 "$demo/enroll.log" >&2; echo "demo failed: enrolment" >&2; exit 1; }
scene=${SCENE:-$demo/scene.yaml}

echo "== starting full_scanner.launch headless: 3 poles x 4 simulated pairs (ROS master on port $port)"
echo "   scene: $scene"
roslaunch -p "$port" body_scan_launch full_scanner.launch gui:=false scene_file:="$scene" \
  calibration_dir:="$demo/calibration" gallery_database:="$gallery" "${walk_args[@]}" \
  ${LAUNCH_ARGS:-} > "$demo/roslaunch.log" 2>&1 &
launch_pid=$!
trap 'kill -INT $launch_pid 2>/dev/null; wait $launch_pid 2>/dev/null || true' EXIT
fail() {
  echo "demo failed: $1; the launch log ($demo/roslaunch.log) ends with:" >&2
  tail -n 40 "$demo/roslaunch.log" >&2
  exit 1
}

# The coordinator advertises /body_scan/capture once it has planned the timing groups; a
# wall-clock deadline, as the pairs' start-up time varies with the machine's load.
deadline=$((SECONDS + 300))
until rosservice list 2>/dev/null | grep -qx /body_scan/capture; do
  [ $SECONDS -lt $deadline ] || fail "/body_scan/capture did not come up within 300 s"
  sleep 0.5
done

# A walk gives 5 answers (its 4 scans, then the walk); a single scan 1.
answers=$([ -n "${SCENE:-}" ] && echo 1 || echo 5)
rosrun body_scan_merge save_cloud _topic:=/body_scan/cloud _output:="$demo/full_scan.ply" \
  _pcd_output:="$demo/full_scan.pcd" _timeout:=180 > "$demo/save_cloud.log" 2>&1 &
save_pid=$!
rostopic echo -n 1 /body_scan/scan_report > "$demo/scan_report.txt" 2>&1 &
report_pid=$!
rostopic echo -n "$answers" /body_gait/identity > "$demo/identity.txt" 2>&1 &
identity_pid=$!
sleep 1
if [ -n "${SCENE:-}" ]; then
  echo "== scanning: the coordinator triggers its timing groups in turn"
  rosservice call /body_scan/capture 0 | tee "$demo/capture_response.txt" || fail "the scan failed"
else
  echo "== walk session: 4 poses, each prompted, taken by the simulated subject and scanned"
  rostopic echo /body_scan/walk_progress > "$demo/walk_progress.txt" 2>&1 &
  progress_pid=$!
  rosservice call /body_scan/capture_walk "{walk_id: 0, pause: -1, trigger: true}" \
    > "$demo/capture_response.txt" || fail "the walk capture failed"
  kill $progress_pid 2>/dev/null || true
  /usr/bin/python3 - "$demo/walk_progress.txt" <<'PY' || true
import sys
import yaml

for part in open(sys.argv[1]).read().split("\n---"):
    progress = yaml.safe_load(part) if part.strip() else None
    if progress and progress.get("state") in (0, 2, 3):  # prompt, scanned, done
        print("   " + progress["prompt"])
PY
  grep -q "success: True" "$demo/capture_response.txt" ||
    { cat "$demo/capture_response.txt"; fail "the walk capture failed"; }
fi
wait $save_pid || { cat "$demo/save_cloud.log" >&2; fail "no merged cloud"; }
wait $report_pid || true
cat "$demo/save_cloud.log"
echo "== scan report (the first scan)"
/usr/bin/python3 - "$demo/scan_report.txt" <<'PY' || cat "$demo/scan_report.txt"
import sys
import yaml

report = yaml.safe_load(open(sys.argv[1]).read().split("\n---")[0])
for key in ("scan_id", "walk_id", "pose_index", "pairs_present", "pairs_missing",
            "points_per_pair", "points_merged", "timing_groups", "simulated_capture_seconds",
            "stage_names", "stage_seconds", "message"):
    value = report.get(key)
    if isinstance(value, list):
        value = ", ".join("%.4g" % v if isinstance(v, float) else str(v) for v in value) or "(none)"
    print("%s: %s" % (key, value))
PY
echo "== merged cloud written to $demo/full_scan.ply and $demo/full_scan.pcd"
echo "   open the file:      pcl_viewer $demo/full_scan.pcd   (or MeshLab / CloudCompare for the PLY)"
echo "   look at it in rviz: source build/devel/setup.bash && roslaunch body_scan_launch full_scanner.launch ${walk_args[*]:-scene_file:=$scene} gallery_database:=$gallery"
if [ -n "${SCENE:-}" ]; then
  echo "                       then: rosservice call /body_scan/capture 0"
else
  echo "                       then: rosservice call /body_scan/capture_walk \"{walk_id: 0, pause: -1, trigger: true}\""
fi
echo "== identification (gait_id_node: fitted models -> the gallery's 240 poses, eq 5.16)"
for _ in $(seq 240); do kill -0 $identity_pid 2>/dev/null || break; sleep 0.5; done
kill $identity_pid 2>/dev/null && fail "not all identities on /body_gait/identity within 120 s"
printf '   scanned: %s\n' "$( [ -n "${SCENE:-}" ] && echo "the person of $scene" ||
  printf 'person_%03d, walk 1, its 4 poses (the gallery holds walk 0)' "$person")"
/usr/bin/python3 - "$demo/identity.txt" <<'PY'
import sys
import yaml

answers = [yaml.safe_load(part) for part in open(sys.argv[1]).read().split("\n---")
           if part.strip()]


def verdict(a):
    return ("accepted" if a["accepted"] else
            "rejected: unknown person (above the threshold %.1f)" % a["threshold"])


for a in sorted(answers, key=lambda a: (a["kind"], a["pose_index"])):
    if a["kind"] == 1:
        ranks = ", ".join("%s %.1f" % (n, s) for n, s in zip(a["ranked_names"], a["ranked_scores"]))
        print("   walk %d identified: subject %d (%s), score %.3f, %s" % (
            a["walk_id"], a["subject_id"], a["name"], a["score"], verdict(a)))
        print("      rank-5: %s" % ranks)
    else:
        where = "pose %d" % a["pose_index"] if a["walk_id"] else "the scan"
        print("   %s alone: subject %d (%s), pose %d of training sequence eta%d, score %.3f, %s" % (
            where, a["subject_id"], a["name"], a["frame"], a["sequence"] + 1, a["score"],
            verdict(a)))
PY
