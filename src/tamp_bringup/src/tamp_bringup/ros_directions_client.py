"""The action client of scripts/record_directions: sends one direction to the semantic_nav node's
`follow_directions` action, prints a progress line every 10 s (which part of the direction, its
predicted class, corners counted, simulated time against the timeout) and the result.
Exit status 0 when the direction was followed, 1 when it failed, 2 on timeout (the goal is
cancelled).

    python3 -m tamp_bringup.ros_directions_client TEXT [--timeout S] [--server-timeout S]
"""
import argparse
import sys
import threading
import time

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from tamp_msgs.msg import FollowDirectionsAction, FollowDirectionsGoal

from tamp_bringup.progress import duration_text, remaining_wall_s

PROGRESS_S = 10.0    # [s] wall-clock period of the progress lines
POLL_S = 0.2         # [s] wall-clock period of the wait for the result
STATES = {GoalStatus.SUCCEEDED: "succeeded", GoalStatus.ABORTED: "aborted",
          GoalStatus.PREEMPTED: "preempted", GoalStatus.REJECTED: "rejected"}


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="ros_directions_client", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("text")
    parser.add_argument("--timeout", type=float, default=240.0,
                        help="cancel after this much simulated time [s]")
    parser.add_argument("--server-timeout", type=float, default=120.0,
                        help="wall time to wait for the action server [s]")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    rospy.init_node("record_directions_client", anonymous=True)
    client = actionlib.SimpleActionClient("follow_directions", FollowDirectionsAction)
    began = time.monotonic()
    while not client.wait_for_server(rospy.Duration(0.5)):
        if rospy.is_shutdown() or time.monotonic() - began > args.server_timeout:
            print(f"[directions] no follow_directions server within {args.server_timeout:g} s",
                  file=sys.stderr)
            return 3
    lock, latest = threading.Lock(), {}

    def on_feedback(feedback):
        with lock:
            latest["feedback"] = feedback

    start_sim, start_wall = rospy.get_time(), time.monotonic()
    client.send_goal(FollowDirectionsGoal(text=args.text), feedback_cb=on_feedback)
    print(f"[directions] sent \"{args.text}\" at {start_sim:.1f} s simulated "
          f"(server up after {time.monotonic() - began:.0f} s)", flush=True)
    next_line = start_wall + PROGRESS_S
    while client.get_state() in (GoalStatus.PENDING, GoalStatus.ACTIVE):
        sim = rospy.get_time() - start_sim
        wall = time.monotonic() - start_wall
        if sim > args.timeout or rospy.is_shutdown():
            client.cancel_goal()
            print(f"[directions] timed out after {sim:.0f} s simulated", file=sys.stderr)
            return 2
        if time.monotonic() >= next_line:
            next_line += PROGRESS_S
            rate = sim / wall if wall > 0 and sim > 0 else 1.0
            with lock:
                feedback = latest.get("feedback")
            part = (f"part {feedback.index + 1} \"{feedback.current}\" (class "
                    f"{feedback.instruction_class}, corners {feedback.corners})"
                    if feedback is not None else "no feedback yet")
            print(f"[directions] {duration_text(wall)}: {part}; simulated {sim:.0f} s of at most "
                  f"{args.timeout:g} s, at most "
                  f"{duration_text(remaining_wall_s(sim, args.timeout, rate))} left", flush=True)
        time.sleep(POLL_S)
    result = client.get_result()
    state = client.get_state()
    sim = rospy.get_time() - start_sim
    success = result is not None and result.success
    print(f"[directions] {STATES.get(state, f'state {state}')} after {sim:.1f} s simulated: "
          f"success {success}, completed {result.completed if result else 0} part(s)"
          + (f", {result.message}" if result is not None and result.message else ""),
          flush=True)
    return 0 if state == GoalStatus.SUCCEEDED and success else 1


if __name__ == "__main__":
    sys.exit(main())
