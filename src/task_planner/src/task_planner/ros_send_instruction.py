"""Command-line tool: publish one instruction on /task_planner/instructions and exit."""
import argparse

import rospy
from tamp_msgs.msg import Instruction as InstructionMsg

from task_planner.conversions import instruction_to_msg
from task_planner.instruction import HUMAN, ROBOT, Instruction, InvalidInstruction
from task_planner.ros_oneshot import publish_when_heard


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--id", type=int, required=True)
    parser.add_argument("--gamma", type=float, required=True, help="initial reward (> 0)")
    parser.add_argument("--beta", type=float, required=True, help="decay per second, in (0, 1)")
    parser.add_argument("--destination", type=int, required=True, help="graph node id")
    parser.add_argument("--destination-name", default="")
    parser.add_argument("--previous-id", type=int, default=0)
    parser.add_argument("--type", choices=("human", "robot"), default="human")
    parser.add_argument("--start-time", type=float, default=None,
                        help="launch time [s]; default: now")
    parser.add_argument("--duration", type=int, default=0, help="function duration [s]")
    parser.add_argument("--source", default="")
    parser.add_argument("--target", default="")
    parser.add_argument("--status", type=int, default=0)
    parser.add_argument("--function", type=int, default=0)
    parser.add_argument("--text", default="")
    parser.add_argument("--wait", type=float, default=5.0,
                        help="wall-clock seconds to wait for a subscriber before giving up")
    return parser.parse_args(argv)


def instruction_from_args(args, now):
    return Instruction(
        id=args.id, gamma=args.gamma, beta=args.beta, destination=args.destination,
        previous_id=args.previous_id, type=ROBOT if args.type == "robot" else HUMAN,
        start_time=now if args.start_time is None else args.start_time, duration=args.duration,
        source=args.source, target=args.target, status=args.status, function=args.function,
        destination_name=args.destination_name, text=args.text)


def main(argv):
    args = parse_args(argv)
    rospy.init_node("send_instruction", anonymous=True)
    try:
        instruction = instruction_from_args(args, rospy.get_time())
    except InvalidInstruction as error:
        rospy.logerr("not sent: %s", error)
        return 2
    publisher = rospy.Publisher("/task_planner/instructions", InstructionMsg,
                                queue_size=1, latch=True)
    if not publish_when_heard(publisher, instruction_to_msg(instruction), args.wait):
        rospy.logerr("not sent: nobody subscribes to /task_planner/instructions after %.1f s",
                     args.wait)
        return 1
    rospy.loginfo("sent instruction %d to node %d", instruction.id, instruction.destination)
    return 0
