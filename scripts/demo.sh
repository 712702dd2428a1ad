#!/usr/bin/env bash
# The main job (make demo): the simulated 12-pair scanner scans a walking subject in the first
# representative gait pose (thesis 5.3), the merged whole-body cloud is written to
# build/demo/full_scan.ply and .pcd, and the scan report is printed. Headless, own ROS master.
#   SCENE=path/to/scene.yaml scripts/demo.sh    (default: the walking subject)
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
scene=${SCENE:-$(rospack find body_scan_driver)/config/scenes/walking_person.yaml}
mkdir -p "$demo" "$ROS_HOME"
rm -f "$demo/full_scan.ply" "$demo/full_scan.pcd"

echo "== starting full_scanner.launch headless: 3 poles x 4 simulated pairs (ROS master on port $port)"
echo "   scene: $scene"
roslaunch -p "$port" body_scan_launch full_scanner.launch gui:=false scene_file:="$scene" \
  calibration_dir:="$demo/calibration" ${LAUNCH_ARGS:-} > "$demo/roslaunch.log" 2>&1 &
launch_pid=$!
trap 'kill -INT $launch_pid 2>/dev/null; wait $launch_pid 2>/dev/null || true' EXIT
fail() {
  echo "demo failed: $1; the launch log ($demo/roslaunch.log) ends with:" >&2
  tail -n 40 "$demo/roslaunch.log" >&2
  exit 1
}

for _ in $(seq 360); do
  rosservice list 2>/dev/null | grep -qx /body_scan/capture && break
  sleep 0.5
done
rosservice list 2>/dev/null | grep -qx /body_scan/capture || fail "/body_scan/capture did not come up"

rosrun body_scan_merge save_cloud _topic:=/body_scan/cloud _output:="$demo/full_scan.ply" \
  _pcd_output:="$demo/full_scan.pcd" _timeout:=180 > "$demo/save_cloud.log" 2>&1 &
save_pid=$!
rostopic echo -n 1 /body_scan/scan_report > "$demo/scan_report.txt" 2>&1 &
report_pid=$!
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
