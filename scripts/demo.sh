#!/usr/bin/env bash
# The main job (make demo): a simulated pair scans a standing person, the cloud is triangulated
# and written to build/demo/single_pair.ply. Runs headless with its own ROS master.
set -euo pipefail
export PATH=/usr/bin:$PATH
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
set +u
source "$root/build/devel/setup.bash"
set -u

port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI="http://localhost:$port"
export ROS_HOME="$root/build/ros_home"
output="$root/build/demo/single_pair.ply"
mkdir -p "$root/build/demo" "$ROS_HOME"

echo "== starting single_pair.launch headless (ROS master on port $port)"
roslaunch -p "$port" body_scan_launch single_pair.launch gui:=false \
  calibration_dir:="$root/build/demo/calibration" > "$root/build/demo/roslaunch.log" 2>&1 &
launch_pid=$!
trap 'kill -INT $launch_pid 2>/dev/null; wait $launch_pid 2>/dev/null || true' EXIT

echo "== waiting for the triangulated cloud on /pole_a/pair_1/points"
if ! rosrun body_scan_merge save_cloud _topic:=/pole_a/pair_1/points _output:="$output" \
     _timeout:=60; then
  echo "demo failed; the launch log follows:" >&2
  tail -n 40 "$root/build/demo/roslaunch.log" >&2
  exit 1
fi
echo "== cloud written to $output"
echo "   factory calibration: $root/build/demo/calibration/pole_a_pair_1_factory.yaml"
echo "   look at it live in rviz:  source build/devel/setup.bash && roslaunch body_scan_launch single_pair.launch"
