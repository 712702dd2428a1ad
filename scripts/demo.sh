#!/usr/bin/env bash
# The main job (make demo): a gait gallery of 6 simulated people is enrolled (walk 0 of each:
# the 4 representative gait poses of thesis 5.3 scanned with the 12-pair simulation, fitted,
# reconstructed to the eta1/eta2 training cycles), then the simulated scanner scans one of them
# on ANOTHER walk (person_003, walk 1, pose 1) through the ROS pipeline: the merged whole-body
# cloud is written to build/demo/full_scan.ply and .pcd, the scan report is printed, the body
# model is fitted and the subject identified (subject, pose, score). Headless, own ROS master.
#   SCENE=path/to/scene.yaml scripts/demo.sh    (another scene; its person is likely unknown)
#   DEMO_PERSON=0..5 scripts/demo.sh            (which enrolled person walks through)
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
mkdir -p "$demo" "$ROS_HOME"
rm -f "$demo/full_scan.ply" "$demo/full_scan.pcd" "$demo/identity.txt"

gallery="$demo/gait_gallery.db"
rm -f "$gallery" "$gallery-wal" "$gallery-shm"
scene_args=(--scene-out "$demo/scene.yaml" --scene-person "$person" --scene-trial 1 --scene-pose 1)
[ -n "${SCENE:-}" ] && scene_args=()
echo "== enrolling 6 simulated people in $gallery: walk 0 of each, 4 poses scanned with the"
echo "   12-pair simulation and fitted (cached in $demo/fit_cache: a re-run takes seconds)"
rosrun body_gait_id enroll_simulated_people --database "$gallery" --people 6 \
  --cache "$demo/fit_cache" "${scene_args[@]}" 2> "$demo/enroll.log" ||
  { tail -n 20 "$demo/enroll.log" >&2; echo "demo failed: enrolment" >&2; exit 1; }
scene=${SCENE:-$demo/scene.yaml}

echo "== starting full_scanner.launch headless: 3 poles x 4 simulated pairs (ROS master on port $port)"
echo "   scene: $scene"
roslaunch -p "$port" body_scan_launch full_scanner.launch gui:=false scene_file:="$scene" \
  calibration_dir:="$demo/calibration" gallery_database:="$gallery" ${LAUNCH_ARGS:-} > "$demo/roslaunch.log" 2>&1 &
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

rosrun body_scan_merge save_cloud _topic:=/body_scan/cloud _output:="$demo/full_scan.ply" \
  _pcd_output:="$demo/full_scan.pcd" _timeout:=180 > "$demo/save_cloud.log" 2>&1 &
save_pid=$!
rostopic echo -n 1 /body_scan/scan_report > "$demo/scan_report.txt" 2>&1 &
report_pid=$!
rostopic echo -n 1 /body_gait/identity > "$demo/identity.txt" 2>&1 &
identity_pid=$!
sleep 1
echo "== scanning: the coordinator triggers its timing groups in turn"
rosservice call /body_scan/capture 0 | tee "$demo/capture_response.txt" || fail "the scan failed"
wait $save_pid || { cat "$demo/save_cloud.log" >&2; fail "no merged cloud"; }
wait $report_pid || true
cat "$demo/save_cloud.log"
echo "== scan report"
grep -E "^(scan_id|pairs_present|pairs_missing|points_per_pair|points_merged|timing_groups|simulated_capture_seconds|stage_names|stage_seconds|message):" \
  "$demo/scan_report.txt" || cat "$demo/scan_report.txt"
echo "== merged cloud written to $demo/full_scan.ply and $demo/full_scan.pcd"
echo "   open the file:      pcl_viewer $demo/full_scan.pcd   (or MeshLab / CloudCompare for the PLY)"
echo "   look at it in rviz: source build/devel/setup.bash && roslaunch body_scan_launch full_scanner.launch scene_file:=$scene"
echo "                       then: rosservice call /body_scan/capture 0"
echo "== identification (gait_id_node: fitted model -> nearest of the gallery's 240 poses, eq 5.16)"
for _ in $(seq 240); do kill -0 $identity_pid 2>/dev/null || break; sleep 0.5; done
kill $identity_pid 2>/dev/null && fail "no identity on /body_gait/identity within 120 s"
value() { sed -n "s/^$1: //p" "$demo/identity.txt" | head -n 1 | tr -d '"'; }
printf '   scanned: %s\n' "$( [ -n "${SCENE:-}" ] && echo "the person of $scene" ||
  printf 'person_%03d, walk 1, pose 1 (the gallery holds walk 0)' "$person")"
printf '   identified: subject %s (%s), pose %s of training sequence eta%s, score %.3f, %s\n' \
  "$(value subject_id)" "$(value name)" "$(value frame)" "$(( $(value sequence) + 1 ))" \
  "$(value score)" "$( [ "$(value accepted)" = True ] && echo accepted || echo "rejected (above the threshold)")"
