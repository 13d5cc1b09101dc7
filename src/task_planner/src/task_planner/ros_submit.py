"""Client of /task_planner/submit for the nodes and tools that give the robot instructions.

`SubmitClient(instruction, previous_id)` sends one request with id 0 (the task buffer allocates
the id, see task_planner.submission) and answers (accepted, id, message); a task planner that is
not up within `timeout_s`, or a failed call, is a refusal whose message says so.
"""
import rospy
from tamp_msgs.srv import SubmitInstruction

from task_planner.conversions import instruction_to_msg

SERVICE = "task_planner/submit"  # relative: a robot's namespace


class SubmitClient:
    def __init__(self, timeout_s=5.0):
        self.timeout_s = float(timeout_s)   # wall-clock wait for the service per request [s]
        self._proxy = rospy.ServiceProxy(SERVICE, SubmitInstruction)

    def __call__(self, instruction, previous_id=None, allocate=True):
        """Submit `instruction` with id 0 (`allocate`; else with its own id) and `previous_id`
        (None: the instruction's own)."""
        msg = instruction_to_msg(instruction)
        if allocate:
            msg.id = 0
        if previous_id is not None:
            msg.previous_id = previous_id
        service = self._proxy.resolved_name
        try:
            rospy.wait_for_service(service, self.timeout_s)
        except rospy.ROSException:
            hint = (" (a fleet's executors answer in their robot's namespace: "
                    "ROS_NAMESPACE=robot1)" if service == "/" + SERVICE else "")
            return False, 0, (f"the task planner is not reachable: {service} is not available "
                              f"after {self.timeout_s:g} s{hint}")
        try:
            reply = self._proxy(instruction=msg)
        except (rospy.ServiceException, rospy.ROSException) as error:
            return False, 0, f"the task planner did not answer on {service}: {error}"
        return reply.accepted, reply.id, reply.message
