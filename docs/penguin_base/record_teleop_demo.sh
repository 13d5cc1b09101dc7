#!/usr/bin/env bash
# Record two teleoperated sequences on the simulated Penguin (tmux send-keys plays the person).
# Writes build/penguin_demo/{demo.bag,launch.log,screen.txt}; uses ROS master port 11473.
set -u
cd "$(dirname "${BASH_SOURCE[0]}")/../.." && OUT="$PWD/build/penguin_demo" && mkdir -p "$OUT"
set +u; source scripts/env.sh; set -u
export ROS_HOME=$OUT/ros ROS_LOG_DIR=$OUT/ros/log ROS_MASTER_URI=http://localhost:11473
roslaunch -p 11473 launch/record_demos.launch bag:=$OUT/demo.bag > $OUT/launch.log 2>&1 &
LAUNCH=$!
sleep 10
T="tmux -L penguin_demo -f /dev/null"
$T new-session -d -s demo -x 120 -y 30 "bash --norc --noprofile"
$T send-keys -t demo "rosrun penguin_base teleop" Enter
until $T capture-pane -p -t demo | grep -q "Penguin teleoperation"; do sleep 0.2; done
sleep 2  # let the teleop's publishers connect
$T send-keys -t demo 1                      # class 1: go straight to the end
for _ in $(seq 10); do $T send-keys -t demo Up; sleep 0.05; done   # 0.20 m/s
sleep 6
$T send-keys -t demo Space; sleep 1; $T send-keys -t demo e; sleep 0.5
$T send-keys -t demo 3                      # class 3: turn left
for _ in $(seq 5); do $T send-keys -t demo Up; sleep 0.05; done    # 0.10 m/s
sleep 1
$T send-keys -t demo Left; sleep 0.5        # held: first press, then repeats at ~30 Hz
for _ in $(seq 20); do $T send-keys -t demo Left; sleep 0.033; done
sleep 1.5
$T capture-pane -p -t demo > $OUT/screen.txt
$T send-keys -t demo Space; sleep 1; $T send-keys -t demo e; sleep 0.5
$T send-keys -t demo q; sleep 2
$T kill-server
kill -INT $LAUNCH; wait $LAUNCH
