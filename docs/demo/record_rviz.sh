#!/usr/bin/env bash
# Screenshot of rviz (config/rviz/social_household.rviz) watching the running household_day
# scenario, headless under Xvfb: docs/demo/rviz_scenario.png.
#   bash docs/demo/record_rviz.sh [SIM_SECONDS]   (default 30: not before this simulated time,
#   and not before rviz has been up for 15 s). utc_offset is the scenario's day_start (18:28).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
at="${1:-30}"
set +u; source scripts/env.sh; set -u
run_dir="$(mktemp -d /tmp/rviz_shot.XXXXXX)"
export ROS_HOME="$run_dir" ROS_LOG_DIR="$run_dir/log"
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://localhost:$port"
display=":$(( 50 + port % 40 ))"
Xvfb "$display" -screen 0 1000x800x24 >"$run_dir/xvfb.log" 2>&1 &
xvfb_pid=$!
launch_pid=""
cleanup() {
  [ -z "$launch_pid" ] || kill -INT "$launch_pid" 2>/dev/null || true
  wait "$launch_pid" 2>/dev/null || true
  kill "$xvfb_pid" 2>/dev/null || true
}
trap cleanup EXIT
DISPLAY="$display" LIBGL_ALWAYS_SOFTWARE=1 roslaunch -p "$port" launch/social_household.launch \
  rviz:=true speed:=2 run_dir:="$run_dir" world:="$ROOT/config/worlds/household_day.yaml" \
  scenario:="$ROOT/config/scenarios/household_day.yaml" record:="$run_dir/record.json" \
  utc_offset:=66480 \
  >"$run_dir/launch.log" 2>&1 &
launch_pid=$!
shot_at="$(python3 - "$at" <<'PY'
import sys
import time

import rosnode
import rospy

rospy.init_node("rviz_shot_clock", anonymous=True)
while not rospy.is_shutdown() and "/rviz" not in rosnode.get_node_names():
    time.sleep(0.5)
time.sleep(15.0)  # rviz loads its displays and draws (software rendering)
from rosgraph_msgs.msg import Clock
def sim_time():  # this helper may start before use_sim_time is set: read /clock itself
    return rospy.wait_for_message("/clock", Clock, 30.0).clock.to_sec()
now = sim_time()
while not rospy.is_shutdown() and now < float(sys.argv[1]):
    time.sleep(0.2)
    now = sim_time()
print(f"{now:.1f}")
PY
)"
DISPLAY="$display" import -window root docs/demo/rviz_scenario.png
echo "[rviz] docs/demo/rviz_scenario.png at simulated time ${shot_at} s (run directory: $run_dir)"
