"""A fault in move_base's control cycle, run as its Supervisor runs it (no roscore: the node is
built without its ROS API, its tf pose and publishers are stubbed)."""
import threading

import pytest
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from helpers import open_room
from supervision.health import ERROR, Health

from nav_mocks.costmap import Costmap, CostmapConfig
from nav_mocks.dwa import DwaConfig
from nav_mocks.move_base_core import MoveBaseConfig, MoveBaseCore
from nav_mocks.ros_move_base import MoveBaseNode

START = (0.6, 0.6, 0.0)


class Recorder:
    def __init__(self):
        self.sent = []

    def publish(self, msg):
        self.sent.append(msg)


class FakeGoalHandle:
    """actionlib's ServerGoalHandle as far as the node uses it; `ends` records how it ended."""

    def __init__(self, goal_id, x, y):
        self.id, self.status, self.ends, self.feedback = goal_id, GoalStatus.PENDING, [], 0
        self.target = PoseStamped()
        self.target.header.frame_id = "map"
        self.target.pose.position.x, self.target.pose.position.y = x, y
        self.target.pose.orientation.w = 1.0

    def get_goal_id(self):
        return type("GoalId", (), {"id": self.id})()

    def get_goal_status(self):
        return GoalStatus(status=self.status)

    def get_goal(self):
        return type("Goal", (), {"target_pose": self.target})()

    def set_accepted(self, _text=""):
        self.status = GoalStatus.ACTIVE

    def publish_feedback(self, _feedback):
        self.feedback += 1

    def _end(self, status, text):
        self.status = status
        self.ends.append((status, text))

    def set_aborted(self, _result, text=""):
        self._end(GoalStatus.ABORTED, text)

    def set_rejected(self, _result, text=""):
        self._end(GoalStatus.REJECTED, text)

    def set_canceled(self, _result, text=""):
        self._end(GoalStatus.PREEMPTED, text)

    def set_succeeded(self, _result, text=""):
        self._end(GoalStatus.SUCCEEDED, text)


@pytest.fixture
def node():
    rospy.rostime.set_rostime_initialized(True)   # ROS time = wall time, no /clock
    node = MoveBaseNode.__new__(MoveBaseNode)
    node.global_frame, node.base_frame, node.period = "map", "base_link", 0.1
    node.lock = threading.Lock()
    node.map_msg = node.scan = node.odom = None
    node.new_goals, node.cancels, node.taken_goals, node.taken_cancels = [], [], [], []
    node.handle, node.goal_note = None, ""
    node.last_cycle = {"duration": 0.0, "status": "idle"}
    node.core = MoveBaseCore(Costmap(open_room(60, 40, resolution=0.05),
                                     CostmapConfig(robot_radius=0.2, inflation_radius=0.4)),
                             MoveBaseConfig(), DwaConfig())
    node.cmd_pub, node.plan_pub = Recorder(), Recorder()
    node.server_started = True
    node._robot_pose = lambda: START
    node.health = Health("nav_mocks: move_base")
    node.health.worker("control", node.period)
    return node


def cycle(node):
    """One control cycle as Supervisor.timer(period, _cycle, on_error=_cycle_failed) runs it."""
    node.health.run("control", "", node._cycle, None, on_error=node._cycle_failed)


def last_cmd(node):
    twist = node.cmd_pub.sent[-1]
    return (twist.linear.x, twist.linear.y, twist.angular.z)


def test_a_control_fault_stops_the_robot_aborts_the_goal_and_the_next_goal_is_served(node):
    first = FakeGoalHandle("first", 2.2, 0.6)
    node.new_goals.append(first)
    cycle(node)
    assert first.status == GoalStatus.ACTIVE and last_cmd(node) != (0.0, 0.0, 0.0)

    def broken_step(*_args):
        raise RuntimeError("local planner exploded")
    working_step, node.core.step = node.core.step, broken_step
    cycle(node)
    assert last_cmd(node) == (0.0, 0.0, 0.0)            # stopped
    assert first.ends == [(GoalStatus.ABORTED, "move_base mock: control cycle failed: "
                                               "RuntimeError: local planner exploded")]
    assert node.handle is None
    level, message, _values = node.health.report()
    assert level == ERROR and "local planner exploded" in message

    node.core.step = working_step
    second = FakeGoalHandle("second", 2.2, 1.2)
    node.new_goals.append(second)
    cycle(node)
    assert second.status == GoalStatus.ACTIVE and second.feedback == 1 and not second.ends
    assert last_cmd(node) != (0.0, 0.0, 0.0)
    assert node.health._workers["control"].failing is False
    assert first.ends == [(GoalStatus.ABORTED, "move_base mock: control cycle failed: "
                                               "RuntimeError: local planner exploded")]


def test_a_fault_while_taking_goals_ends_every_goal_the_cycle_took(node):
    goals = [FakeGoalHandle(name, 2.2, 0.6) for name in ("a", "b", "c")]
    node.new_goals.extend(goals)
    calls = []

    def start_goal(goal, now, pose, real=node.core.start_goal):
        calls.append(goal)
        if len(calls) == 2:
            raise ValueError("bad goal arithmetic")
        return real(goal, now, pose)
    node.core.start_goal = start_goal
    cycle(node)
    reason = "move_base mock: control cycle failed: ValueError: bad goal arithmetic"
    assert goals[0].ends == [(GoalStatus.ABORTED, reason)]     # accepted, then the fault
    assert goals[1].ends == [(GoalStatus.REJECTED, reason)]    # its own handling raised
    assert goals[2].ends == [(GoalStatus.REJECTED, reason)]    # never reached
    assert last_cmd(node) == (0.0, 0.0, 0.0)
    assert node.handle is None and not node.taken_goals
