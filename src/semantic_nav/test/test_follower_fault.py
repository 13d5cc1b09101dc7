"""The node's control step run as its Supervisor runs it: a fault in it, a direction announced,
a direction asked back (no roscore: the node is built without its ROS API; actionlib's
SimpleActionServer and the publishers are stubbed)."""
import threading
import types

import pytest
import rospy
from actionlib_msgs.msg import GoalStatus
from sensor_msgs.msg import LaserScan
from supervision.health import ERROR, Health

from semantic_nav.asking_back import AskConfig
from semantic_nav.follow_session import DECLINED, STOPPED
from semantic_nav.follower import FollowerCommand
from semantic_nav.splitting import split_instruction
from semantic_nav.ros_follower import FollowerNode, NodeParams

SENTENCE = "go straight to the end, then turn left"
FAULT_SPOKEN = ("Sorry, I had to stop following your directions: my controller failed "
                "(RuntimeError: network exploded). I am staying here.")


class Follower:
    """Drives at 0.3 m/s until `arrived`; `broken` makes its step (or its start) raise."""

    control_period = 0.1
    doorway_points = []
    guard_actions = {}
    corrections = []

    def __init__(self):
        self.broken = None   # None, "step" or "start"
        self.arrived = False

    def start(self, sentence):
        if self.broken == "start":
            raise RuntimeError("network exploded")
        self.instructions = split_instruction(sentence)
        return [1, 3]

    def step(self, ranges, laser):
        if self.broken == "step":
            raise RuntimeError("network exploded")
        return FollowerCommand(0.3, 0.1, 0, 1, self.arrived)


class Recorder:
    def __init__(self):
        self.sent = []

    def publish(self, msg):
        self.sent.append(msg)

    def get_num_connections(self):
        return 0


class FakeServer:
    """actionlib's SimpleActionServer as far as the node uses it: one current goal; a new goal
    cancels the active one and calls the goal callback (as actionlib does, under its locks)."""

    def __init__(self):
        self.action_server = types.SimpleNamespace(lock=threading.RLock())
        self.lock = threading.RLock()
        self.current_goal, self.next = None, None
        self.ends = {}           # goal id -> [(status, text)]
        self.status, self.feedback = {}, []

    def send(self, goal_id, text, goal_callback):
        with self.action_server.lock, self.lock:
            self.next = (goal_id, text)
            goal_callback()

    def accept_new_goal(self):
        if self.is_active():
            self._end(GoalStatus.PREEMPTED, "canceled: another goal was received")
        goal_id, text = self.next
        self.current_goal = types.SimpleNamespace(
            get_goal_id=lambda: types.SimpleNamespace(id=goal_id))
        self.status[goal_id] = GoalStatus.ACTIVE
        return types.SimpleNamespace(text=text)

    def _id(self):
        return self.current_goal.get_goal_id().id

    def is_active(self):
        return self.current_goal is not None and self.status[self._id()] == GoalStatus.ACTIVE

    def is_preempt_requested(self):
        return False

    def publish_feedback(self, feedback):
        self.feedback.append((self._id(), feedback))

    def _end(self, status, text):
        assert self.is_active(), "a goal ended twice"
        self.status[self._id()] = status
        self.ends.setdefault(self._id(), []).append((status, text))

    def set_succeeded(self, _result=None, text=""):
        self._end(GoalStatus.SUCCEEDED, text)

    def set_aborted(self, result=None, text=""):
        self._end(GoalStatus.ABORTED, text)
        self.last_result = result

    def set_preempted(self, _result=None, text=""):
        self._end(GoalStatus.PREEMPTED, text)


class FakeSupervisor:
    """Supervisor.worker/wrap on a ROS-free Health."""

    def __init__(self):
        self.health = Health("semantic_nav: semantic_nav")

    def worker(self, name, period_s=None):
        self.health.worker(name, period_s)

    def wrap(self, worker, callback, on_error=None):
        return lambda arg: self.health.run(worker, "", callback, arg, on_error=on_error)


def scan():
    msg = LaserScan(angle_min=-2.35, angle_increment=0.0043633, range_max=30.0,
                    ranges=[3.0] * 1081)
    msg.header.frame_id = "laser"
    return msg


@pytest.fixture
def node():
    rospy.rostime.set_rostime_initialized(True)   # ROS time = wall time, no /clock
    node = FollowerNode(NodeParams(), Follower())
    node.cmd_pub, node.say_pub, node.marker_pub, node.doorway_pub = (Recorder(), Recorder(),
                                                                     Recorder(), Recorder())
    node.server = FakeServer()
    node.sup = FakeSupervisor()
    node.sup.worker("control", 0.1)
    node.goal_callback = node.guarded("goal callback", node._on_goal, node._goal_failed)
    return node


def tick(node):
    """One control step as Supervisor.timer(period, _tick, on_error=_step_failed) runs it."""
    with node.lock:
        node.scan, node.scan_stamp = scan(), rospy.get_time()
    node.sup.health.run("control", "", node._tick, None, on_error=node._step_failed)


def last_cmd(node):
    msg = node.cmd_pub.sent[-1]
    return (msg.linear.x, msg.angular.z)


def test_a_control_step_fault_stops_aborts_says_why_and_the_next_goal_is_followed(node):
    node.server.send("first", SENTENCE, node.goal_callback)
    tick(node)
    assert last_cmd(node) == pytest.approx((0.3, 0.1)) and node.session is not None

    node.follower.broken = "step"
    tick(node)
    reason = "control step failed: RuntimeError: network exploded"
    assert last_cmd(node) == (0.0, 0.0)                          # stopped at once
    assert node.server.ends["first"] == [(GoalStatus.ABORTED, reason)]
    assert node.server.last_result.message == reason and not node.server.last_result.success
    assert [m.data for m in node.say_pub.sent] == [FAULT_SPOKEN]
    assert node.session is None and node.last_result == reason
    level, message, _values = node.sup.health.report()
    assert level == ERROR and "network exploded" in message

    tick(node)                                 # a fault is reported once, not per step
    assert node.server.ends["first"] == [(GoalStatus.ABORTED, reason)]
    assert len(node.say_pub.sent) == 1

    node.follower.broken = None
    node.server.send("second", SENTENCE, node.goal_callback)
    tick(node)
    assert last_cmd(node) == pytest.approx((0.3, 0.1))
    assert node.server.status["second"] == GoalStatus.ACTIVE and "second" not in node.server.ends
    assert node.server.feedback[-1][0] == "second"
    assert node.sup.health._workers["control"].failing is False


def test_a_fault_while_a_goal_is_started_ends_that_goal(node):
    node.follower.broken = "start"
    node.server.send("first", SENTENCE, node.goal_callback)
    tick(node)
    reason = "control step failed: RuntimeError: network exploded"
    assert node.server.ends["first"] == [(GoalStatus.ABORTED, reason)]
    assert [m.data for m in node.say_pub.sent] == [FAULT_SPOKEN]
    assert last_cmd(node) == (0.0, 0.0) and node.sentence is None

    node.follower.broken = None
    node.server.send("second", SENTENCE, node.goal_callback)
    tick(node)
    assert node.server.status["second"] == GoalStatus.ACTIVE
    assert last_cmd(node) == pytest.approx((0.3, 0.1))


def test_a_fault_while_the_old_sentence_ends_also_ends_the_goal_taken(node):
    with node.lock:
        node.voice = SENTENCE
    tick(node)                                                   # following a spoken sentence
    assert node.source == "/voice_message"

    def broken_stop(reason):
        raise RuntimeError("network exploded")
    node.session.stop = broken_stop
    node.server.send("goal", SENTENCE, node.goal_callback)
    tick(node)              # replacing the sentence raises before the goal is started
    assert node.server.ends["goal"] == [(GoalStatus.ABORTED, "control step failed: "
                                                             "RuntimeError: network exploded")]
    assert last_cmd(node) == (0.0, 0.0) and node.session is None


def test_a_goal_callback_fault_ends_the_accepted_goal(node):
    def broken_store():
        node.server.accept_new_goal()
        raise KeyError("goal cache")
    broken = node.guarded("goal callback", broken_store, node._goal_failed)
    node.server.send("first", SENTENCE, broken)
    assert node.server.ends["first"] == [(GoalStatus.ABORTED,
                                          "goal callback failed: KeyError: 'goal cache'")]
    node.server.send("second", SENTENCE, node.goal_callback)
    tick(node)
    assert node.server.status["second"] == GoalStatus.ACTIVE



def test_a_voice_message_direction_that_ends_is_announced(node):
    with node.lock:
        node.voice = SENTENCE
    tick(node)
    assert node.source == "/voice_message" and node.say_pub.sent == []
    node.follower.arrived = True
    tick(node)
    assert last_cmd(node) == (0.0, 0.0) and node.session is None
    assert [m.data for m in node.say_pub.sent] == ["I have arrived."]


class MisheardFollower(Follower):
    """Reads "lift" as "left" (a misheard word): the node asks back before it drives."""

    config = types.SimpleNamespace(ask=AskConfig())

    def start(self, sentence):
        classes = super().start(sentence)
        self.corrections = [("lift", "left")] if "lift" in sentence else []
        self.confidences, self.countings, self.unknown_words = [0.99, 0.99], [], []
        return classes


def test_an_unsure_direction_waits_for_a_yes_and_a_no_stops_a_drive(node):
    node.follower = MisheardFollower()
    node.server.send("asked", "go to the end, then turn lift", node.goal_callback)
    tick(node)
    question = ("I understood: go straight to the end, then take the first left. Shall I go? "
                "Please say yes or no.")
    assert [m.data for m in node.say_pub.sent] == [question]
    assert last_cmd(node) == (0.0, 0.0) and node.session.asking
    assert node.server.feedback[-1][1].question == question
    with node.lock:
        node.voice = "No."
    tick(node)
    assert node.server.ends["asked"][0][0] == GoalStatus.ABORTED
    assert node.say_pub.sent[-1].data == DECLINED and node.session is None

    node.server.send("yes", "go to the end, then turn lift", node.goal_callback)
    tick(node)
    with node.lock:
        node.voice = "yes please"
    tick(node)
    assert last_cmd(node) == pytest.approx((0.3, 0.1)) and not node.session.asking
    with node.lock:
        node.voice = "stop"                 # a no while it drives stops the robot
    tick(node)
    assert last_cmd(node) == (0.0, 0.0) and node.session is None
    assert node.server.ends["yes"][0][0] == GoalStatus.ABORTED
    assert node.say_pub.sent[-1].data == STOPPED

