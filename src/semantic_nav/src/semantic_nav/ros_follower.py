"""The semantic_nav node: FollowDirections action server and /voice_message input in front of
the direction follower (scan -> laser layer -> network -> post-processing -> /cmd_vel).

Callbacks only cache under a lock (scan, odometry, new goal, preemption, voice sentence); a
timer at the follower's control period does the work. The robot is stopped (zero /cmd_vel) on
preemption, when no scan arrives for ~scan_timeout, when a sentence ends and on exit. A sentence
the follower must not try (a corner beyond the third, not English, no known word) is refused
before the robot moves, and the reason is said on /robot/say; so is the end of a sentence that
ends by itself ("I have arrived.", or why it was not finished in ~max_duration), from
/voice_message or the action alike (follow_session). A sentence the follower is not sure of is
asked back first (asking_back): the robot says what it understood on /robot/say and stands still
until a yes on /voice_message; a no or silence ends it, any other utterance replaces it. A no
while the robot drives stops it.

Every timer, subscriber and action server callback runs under one
supervision.ros_supervisor.Supervisor ("semantic_nav: semantic_nav: supervision"): a fault in
the control step stops the robot at once, ends the sentence being followed (its action goal
aborted) with the reason, says the reason on /robot/say, and the next step takes the next goal.
"""
import math
import threading
from dataclasses import dataclass

import actionlib
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from tamp_msgs.msg import FollowDirectionsAction, Utterance
from visualization_msgs.msg import Marker

from semantic_nav.asking_back import read_answer
from semantic_nav.collision_guard import format_guard_actions
from semantic_nav.conversions import (doorway_marker, feedback_msg, path_marker, result_msg,
                                      scan_to_core, twist)
from semantic_nav.follow_session import (ABORTED, SUCCEEDED, FollowSession, InstructionRefused,
                                         Outcome, step_failed)
from semantic_nav.instruction_layer import read_transcript
from semantic_nav.misheard import read_as
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor


@dataclass(frozen=True)
class NodeParams:
    model: str = ""               # model file; "" = the follower's default (make train)
    word_vectors: str = ""        # GloVe source; "" = the compact cache of scripts/setup
    follower_config: str = ""     # follower YAML; "" = its defaults
    scan_timeout: float = 0.5     # no scan for this long: stop the robot [s]
    max_duration: float = 300.0   # a sentence not finished after this long is aborted [s]
    path_frame: str = "odom"      # frame of the driven-path marker (that of /odom)
    path_spacing: float = 0.05    # add a path point every this far [m]
    marker_width: float = 0.05    # [m]

    @classmethod
    def from_ros(cls):
        """Every field from the private parameter of the same name (default if unset)."""
        return config_from_params(cls)


class FollowerNode:
    def __init__(self, params, follower):
        self.params, self.follower = params, follower
        self.lock = threading.Lock()   # guards the caches below
        self.scan, self.scan_stamp, self.pose = None, None, None
        self.voice, self.preempted, self.new_goal = None, False, None
        # the sentence being started or followed: its text, session, source and action goal id
        self.sentence, self.session, self.source, self.goal_id = None, None, None, None
        self.taken_goal = None   # (text, goal id) the control step took and has not started yet
        self.path = []
        self.last_result = ""

    def setup(self, sup):
        """Start the ROS API under the node's Supervisor `sup`."""
        self.sup = sup
        self.cmd_pub = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        self.say_pub = rospy.Publisher("robot/say", String, queue_size=5)
        self.marker_pub = rospy.Publisher("~path", Marker, queue_size=1, latch=True)
        self.doorway_pub = rospy.Publisher("~doorways", Marker, queue_size=1)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.server = actionlib.SimpleActionServer("follow_directions", FollowDirectionsAction,
                                                   auto_start=False)
        self.server.register_goal_callback(
            self.guarded("goal callback", self._on_goal, self._goal_failed))
        self.server.register_preempt_callback(self.guarded("preempt callback", self._on_preempt))
        sup.subscriber("scan", LaserScan, self._on_scan, queue_size=1)
        sup.subscriber("odom", Odometry, self._on_odom, queue_size=1)
        sup.subscriber("voice_message", Utterance, self._on_voice, queue_size=5)
        self.server.start()
        sup.timer(self.follower.control_period, self._tick, worker="control",
                  on_error=self._step_failed)
        sup.timer(1.0, self._diagnose, worker="diagnostics")
        rospy.on_shutdown(self._stop_robot)
        return True

    def guarded(self, worker, callback, on_error=None):
        """A callback without arguments (actionlib's goal and preempt callbacks) under the
        Supervisor as worker `worker`."""
        self.sup.worker(worker)
        run = self.sup.wrap(worker, lambda _arg: callback(), on_error)
        return lambda: run(None)

    # ---- callbacks: cache only ----
    def _on_scan(self, msg):
        with self.lock:
            self.scan, self.scan_stamp = msg, rospy.get_time()

    def _on_odom(self, msg):
        with self.lock:
            self.pose = (msg.pose.pose.position.x, msg.pose.pose.position.y)

    def _on_voice(self, msg):
        """The utterance the phone app or speech-to-text publishes (tamp_msgs/Utterance, as for
        the social robot's perception): its text, read as a transcript (read_transcript), is the
        sentence to follow."""
        sentence = read_transcript(msg.text)
        with self.lock:
            self.voice = sentence

    def _on_goal(self):
        goal = self.server.accept_new_goal()
        goal_id = self.server.current_goal.get_goal_id().id
        with self.lock:
            self.new_goal, self.preempted = (goal.text, goal_id), False

    def _goal_failed(self, error):
        """The goal callback raised (actionlib holds its locks): an accepted goal the control
        step was not handed ends aborted with the reason."""
        reason = f"goal callback failed: {fault_text(error)}"
        with self.lock:
            handed = {goal[1] for goal in (self.new_goal, self.taken_goal) if goal is not None}
        handed.add(self.goal_id)
        if self.server.is_active() and self.server.current_goal.get_goal_id().id not in handed:
            self.server.set_aborted(result_msg(reason), reason)

    def _on_preempt(self):
        with self.lock:
            self.preempted = True

    # ---- work: the control timer ----
    def _stop_robot(self):
        self.cmd_pub.publish(twist(0.0, 0.0))

    def _end_goal(self, outcome, goal_id, fault=False):
        """End action goal `goal_id` with `outcome`, unless actionlib already ended it or a newer
        goal replaced it. Under actionlib's locks, in the order its goal callback holds them, so
        no goal is accepted in between."""
        with self.server.action_server.lock, self.server.lock:
            if not self.server.is_active() or \
                    self.server.current_goal.get_goal_id().id != goal_id:
                return
            result = result_msg(outcome)
            if outcome.status == SUCCEEDED:
                self.server.set_succeeded(result, outcome.message)
            elif self.server.is_preempt_requested() and not fault:
                self.server.set_preempted(result, outcome.message)
            else:
                self.server.set_aborted(result, outcome.message)

    def _finish(self, outcome, fault=False):
        """End the current sentence with `outcome`: stop, report to its action goal (aborted on
        a `fault`), say the spoken reason, log."""
        self._stop_robot()
        self.last_result = outcome.message
        if self.goal_id is not None:
            self._end_goal(outcome, self.goal_id, fault)
        if outcome.spoken:
            self.say_pub.publish(String(data=outcome.spoken))
        log = rospy.logerr if fault else rospy.logwarn if outcome.spoken else rospy.loginfo
        log("semantic_nav: %r: %s", self.sentence, outcome.message)
        self.sentence, self.session, self.source, self.goal_id = None, None, None, None

    def _step_failed(self, error):
        """The control step raised: stop the robot at once, end the sentence being started or
        followed as aborted with the reason (its action goal too) and say it; the next step
        takes the next goal as usual. A goal the step took but had not started ends too."""
        self._stop_robot()
        taken, self.taken_goal = self.taken_goal, None
        if self.session is not None:
            self._finish(self.session.fail(error), fault=True)
        elif self.sentence is not None:      # raised while it was being started
            self._finish(step_failed(error), fault=True)
        else:
            rospy.logerr("semantic_nav: control step failed: %s; robot stopped",
                         fault_text(error))
        if taken is not None:
            self._end_goal(step_failed(error), taken[1], fault=True)

    def _begin(self, sentence, source, now, goal_id=None):
        if self.session is not None:     # replaced (actionlib already ended a replaced goal)
            self._finish(self.session.stop(f"replaced by a new instruction from {source}"))
        self.sentence, self.source, self.goal_id, self.path = sentence, source, goal_id, []
        if goal_id is not None:
            self.taken_goal = None
        try:
            self.session = FollowSession(self.follower, sentence, now, self.params.max_duration)
        except InstructionRefused as error:
            self._finish(Outcome(ABORTED, 0, str(error), error.spoken))
            return
        corrections = read_as(self.follower.corrections)
        rospy.loginfo("semantic_nav: following %r (%s): classes %s%s", sentence, source,
                      self.session.classes, f"; read {corrections}" if corrections else "")
        if self.session.asking:
            self._stop_robot()
            self.say_pub.publish(String(data=self.session.question))
            rospy.loginfo("semantic_nav: not sure (%s): asked %r", "; ".join(self.session.unsure),
                          self.session.question)

    def _on_reply(self, reply, now):
        """A yes or no on /voice_message, for the sentence being asked about or followed
        (FollowSession.answer)."""
        if self.session is None:
            rospy.loginfo("semantic_nav: %r heard with no direction: nothing to do", reply)
            return
        rospy.loginfo("semantic_nav: %r heard (%s)", reply,
                      f"to {self.session.question!r}" if self.session.asking else "driving")
        self.session.answer(reply, now)
        if self.session.outcome is not None:
            self._finish(self.session.outcome)

    def _take_inputs(self):
        with self.lock:
            inputs = (self.new_goal, self.voice, self.preempted, self.scan, self.scan_stamp,
                      self.pose)
            self.new_goal, self.voice, self.preempted = None, None, False
        return inputs

    def _tick(self, _event):
        goal, voice, preempted, scan, stamp, pose = self._take_inputs()
        self.taken_goal = goal
        now = rospy.get_time()
        if goal is not None:
            self._begin(goal[0], "action", now, goal_id=goal[1])
        elif preempted and self.session is not None and self.source == "action":
            self._finish(self.session.stop("preempted"))
        if voice is not None:
            reply = read_answer(voice)
            if reply is not None:       # a yes or a no, not a direction
                self._on_reply(reply, now)
            else:
                self._begin(voice, "/voice_message", now)
        if self.session is None:
            return
        if self.session.asking:        # stands still until the answer or its time limit
            self._wait_for_answer(now)
            return
        if scan is None or now - stamp > self.params.scan_timeout:
            self._stop_robot()
            rospy.logwarn_throttle(2.0, "semantic_nav: no scan on /scan for %.1f s: stopped",
                                   math.inf if stamp is None else now - stamp)
            return
        self._control(scan, pose, now)

    def _wait_for_answer(self, now):
        feedback = self.session.wait(now)
        if self.session.outcome is not None:
            self._finish(self.session.outcome)
            return
        self._stop_robot()
        if self.source == "action":
            self.server.publish_feedback(feedback_msg(feedback, self.session.question))

    def _control(self, scan, pose, now):
        ranges, laser = scan_to_core(scan)
        v, w, feedback = self.session.step(ranges, laser, now)
        if self.session.outcome is not None:
            self._finish(self.session.outcome)
            return
        self.cmd_pub.publish(twist(v, w))
        if self.doorway_pub.get_num_connections():     # built only for a listener (rviz)
            self.doorway_pub.publish(doorway_marker(self.follower.doorway_points,
                                                    scan.header.frame_id, scan.header.stamp,
                                                    self.params.marker_width))
        if self.source == "action":
            self.server.publish_feedback(feedback_msg(feedback))
        if pose is not None and (not self.path or math.dist(self.path[-1], pose) >
                                 self.params.path_spacing):
            self.path.append(pose)
            self.marker_pub.publish(path_marker(self.path, self.params.path_frame,
                                                rospy.Time.now(), self.params.marker_width))

    def _diagnose(self, _event):
        with self.lock:
            stamp = self.scan_stamp
        age = math.inf if stamp is None else rospy.get_time() - stamp
        status = DiagnosticStatus(name="semantic_nav", hardware_id="direction_follower")
        if age > self.params.scan_timeout:
            status.level, status.message = DiagnosticStatus.ERROR, f"no scan for {age:.1f} s"
        elif self.session is not None and self.session.asking:
            status.level, status.message = DiagnosticStatus.OK, "asking"
        elif self.session is not None:
            status.level, status.message = DiagnosticStatus.OK, "following"
        else:
            status.level, status.message = DiagnosticStatus.OK, "idle"
        session = self.session
        status.values = [KeyValue("scan_age_s", f"{age:.2f}"),
                         KeyValue("sentence", session.sentence if session else ""),
                         KeyValue("index", str(session.index) if session else ""),
                         KeyValue("question", session.question if session and session.asking
                                  else ""),
                         KeyValue("last_result", self.last_result),
                         KeyValue("guard", format_guard_actions(self.follower.guard_actions)),
                         KeyValue("doorway_beams", str(len(self.follower.doorway_points)))]
        self.diag_pub.publish(DiagnosticArray(header=rospy.Header(stamp=rospy.Time.now()),
                                              status=[status]))


def main():
    rospy.init_node("semantic_nav")
    params = NodeParams.from_ros()
    from semantic_nav.follower import DirectionFollower
    try:       # a missing model names `make train`; a bad follower YAML names its key
        follower = DirectionFollower.from_files(params.model or None,
                                                params.word_vectors or None,
                                                params.follower_config or None)
    except (OSError, ValueError) as error:
        rospy.logfatal("semantic_nav: %s", error)
        return 1
    node = FollowerNode(params, follower)
    node.setup(Supervisor("semantic_nav: semantic_nav", hardware_id="direction_follower"))
    rospy.loginfo("semantic_nav: ready (action follow_directions, /voice_message)")
    rospy.spin()
    return 0
