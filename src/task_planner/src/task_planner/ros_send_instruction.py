"""Command-line tool: submit one instruction on task_planner/submit, print its id and exit.

The service name is relative: /task_planner/submit, or /robot1/task_planner/submit with
ROS_NAMESPACE=robot1, as a fleet's executors run in their robot's namespace (--help says so).

Without --id (or with --id 0) the task buffer allocates the id; a chain's successor names the id
printed for its predecessor with --previous-id. The start time defaults to the present ROS time
(under simulated time the tool waits for /clock). --function, --status and --destination take
a name or a number (task_planner.send_instruction_args; --help lists the names). Exit status: 0
accepted, 1 refused or the task planner not reachable within --wait, 2 an invalid instruction
or an unknown name (nothing sent).
"""
import time

import rospy

from task_planner.instruction import InvalidInstruction
from task_planner.ros_submit import SERVICE, SubmitClient
from task_planner.send_instruction_args import instruction_from_args, parse_args


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
    args = parse_args(argv, __doc__.splitlines()[0], SERVICE)
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
