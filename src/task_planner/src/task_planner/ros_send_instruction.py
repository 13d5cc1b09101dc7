"""Command-line tool: submit one instruction on /task_planner/submit, print its id and exit.

Without --id (or with --id 0) the task buffer allocates the id; a chain's successor names the id
printed for its predecessor with --previous-id. The start time defaults to the present ROS time
(under simulated time the tool waits for /clock). Exit status: 0 accepted, 1 refused or the task
planner not reachable within --wait, 2 an invalid instruction (nothing sent).
"""
import argparse
import time

import rospy

from task_planner.instruction import HUMAN, ROBOT, Instruction, InvalidInstruction
from task_planner.ros_submit import SERVICE, SubmitClient


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--id", type=int, default=0,
                        help="instruction id; 0 (default): the task buffer allocates it")
    parser.add_argument("--gamma", type=float, required=True, help="initial reward (> 0)")
    parser.add_argument("--beta", type=float, required=True, help="decay per second, in (0, 1)")
    parser.add_argument("--destination", type=int, required=True, help="graph node id")
    parser.add_argument("--destination-name", default="")
    parser.add_argument("--previous-id", type=int, default=0)
    parser.add_argument("--type", choices=("human", "robot"), default="human")
    parser.add_argument("--start-time", type=float, default=None,
                        help="launch time [s, ROS time]; default: now")
    parser.add_argument("--duration", type=int, default=0, help="function duration [s]")
    parser.add_argument("--source", default="")
    parser.add_argument("--target", default="")
    parser.add_argument("--status", type=int, default=0)
    parser.add_argument("--function", type=int, default=0)
    parser.add_argument("--text", default="")
    parser.add_argument("--wait", type=float, default=5.0,
                        help="wall-clock seconds to wait for ROS time and for "
                             f"{SERVICE} before giving up")
    return parser.parse_args(argv)


def instruction_from_args(args, now):
    """The Instruction to submit, checked here; with --id 0 a provisional id stands in for the
    one the task buffer allocates (task_planner.submission)."""
    provisional = args.id or args.previous_id + 1
    return Instruction(
        id=provisional, gamma=args.gamma, beta=args.beta, destination=args.destination,
        previous_id=args.previous_id, type=ROBOT if args.type == "robot" else HUMAN,
        start_time=now if args.start_time is None else args.start_time, duration=args.duration,
        source=args.source, target=args.target, status=args.status, function=args.function,
        destination_name=args.destination_name, text=args.text)


def ros_now(wait_s):
    """The present ROS time [s], waiting up to `wait_s` of wall-clock time for a simulated clock
    to start; None when it has not."""
    deadline = time.monotonic() + wait_s
    while rospy.Time.now().is_zero():
        if time.monotonic() >= deadline or rospy.is_shutdown():
            return None
        time.sleep(0.05)
    return rospy.Time.now().to_sec()


def main(argv):
    args = parse_args(argv)
    rospy.init_node("send_instruction", anonymous=True)
    now = ros_now(args.wait) if args.start_time is None else args.start_time
    if now is None:
        rospy.logerr("not sent: ROS time is still 0 after %.1f s (/use_sim_time is set and "
                     "nothing publishes /clock?)", args.wait)
        return 1
    try:
        instruction = instruction_from_args(args, now)
    except InvalidInstruction as error:
        rospy.logerr("not sent: %s", error)
        return 2
    accepted, instruction_id, message = SubmitClient(args.wait)(instruction,
                                                                allocate=args.id == 0)
    if not accepted:
        rospy.logerr("not accepted: %s", message)
        return 1
    rospy.loginfo("instruction %d accepted for node %d", instruction_id, instruction.destination)
    print(instruction_id)
    return 0
