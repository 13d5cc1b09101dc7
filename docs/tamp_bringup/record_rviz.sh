#!/usr/bin/env bash
# Screenshots of the two rviz views with the robot models, headless under Xvfb (software GL):
#   bash docs/tamp_bringup/record_rviz.sh household   -> docs/tamp_bringup/rviz_household.png
#     social_household.launch rviz:=true playing config/scenarios/household_day.yaml at 2x,
#     taken at 76 s of simulated time (the first requests are being served)
#   bash docs/tamp_bringup/record_rviz.sh directions  -> docs/tamp_bringup/rviz_directions.png
#     semantic_nav.launch rviz:=true on office_ring; "go straight to the end, then turn left"
#     on /voice_message, taken 90 s of simulated time later (the robot has arrived and stopped)
#   bash docs/tamp_bringup/record_rviz.sh fleet       -> docs/tamp_bringup/rviz_fleet.png
#     household_fleet.launch rviz:=true playing config/scenarios/household_day.yaml at 2x with
#     two robots, taken at 100 s of simulated time
# SIM_SECONDS (second argument) replaces the time of the shot.
# Each run has its own roscore port, ROS_HOME and X display, and stops everything it started.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
view="${1:?usage: record_rviz.sh household|directions|fleet [SIM_SECONDS]}"
set +u; source scripts/env.sh; set -u
run_dir="$(mktemp -d /tmp/rviz_shot.XXXXXX)"
export ROS_HOME="$run_dir" ROS_LOG_DIR="$run_dir/log" ROS_HOSTNAME=localhost
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://localhost:$port"
display=":$(( 50 + port % 40 ))"
case "$view" in
  household)
    size=1000x800; out=docs/tamp_bringup/rviz_household.png; sentence=""; at=76
    launch=(social_household.launch rviz:=true speed:=2 run_dir:="$run_dir"
            world:="$(rospack find tamp_resources)/config/worlds/household_day.yaml"
            scenario:="$(rospack find tamp_resources)/config/scenarios/household_day.yaml"
            record:="$run_dir/record.json" utc_offset:=66480) ;;
  directions)
    size=1200x800; out=docs/tamp_bringup/rviz_directions.png; at=90
    sentence="go straight to the end, then turn left"
    launch=(semantic_nav.launch rviz:=true floor:=office_ring) ;;
  fleet)
    size=1000x800; out=docs/tamp_bringup/rviz_fleet.png; sentence=""; at=100
    launch=(household_fleet.launch rviz:=true speed:=2 run_dir:="$run_dir"
            scenario:="$(rospack find tamp_resources)/config/scenarios/household_day.yaml"
            record:="$run_dir/record.json" utc_offset:=66480) ;;
  *) echo "unknown view $view (household, directions or fleet)" >&2; exit 2 ;;
esac
at="${2:-$at}"
Xvfb "$display" -screen 0 "${size}x24" >"$run_dir/xvfb.log" 2>&1 &
xvfb_pid=$!
launch_pid=""
cleanup() {
  [ -z "$launch_pid" ] || kill -INT "$launch_pid" 2>/dev/null || true
  [ -z "$launch_pid" ] || wait "$launch_pid" 2>/dev/null || true
  kill "$xvfb_pid" 2>/dev/null || true
}
trap cleanup EXIT
DISPLAY="$display" LIBGL_ALWAYS_SOFTWARE=1 roslaunch -p "$port" tamp_bringup "${launch[@]}" \
  >"$run_dir/launch.log" 2>&1 &
launch_pid=$!
shot_at="$(python3 - "$at" "$sentence" <<'PY'
import sys
import time

import rosnode
import rospy
from rosgraph_msgs.msg import Clock

rospy.init_node("rviz_shot_clock", anonymous=True)
while not rospy.is_shutdown() and "/rviz" not in rosnode.get_node_names():
    time.sleep(0.5)
time.sleep(15.0)  # rviz loads its displays and draws (software rendering)


def sim_time():  # this helper may start before use_sim_time is set: read /clock itself
    return rospy.wait_for_message("/clock", Clock, 30.0).clock.to_sec()


until = float(sys.argv[1])
if sys.argv[2]:
    from tamp_msgs.msg import Utterance
    pub = rospy.Publisher("/voice_message", Utterance, queue_size=1, latch=True)
    while not rospy.is_shutdown() and pub.get_num_connections() == 0:
        time.sleep(0.2)
    pub.publish(Utterance(text=sys.argv[2]))
    until += sim_time()
now = sim_time()
while not rospy.is_shutdown() and now < until:
    time.sleep(0.2)
    now = sim_time()
print(f"{now:.1f}")
time.sleep(5.0)  # software rendering lags: let rviz draw what arrived last
PY
)"
DISPLAY="$display" import -window root "$out"
echo "[rviz] $out at simulated time ${shot_at} s (run directory: $run_dir)"
