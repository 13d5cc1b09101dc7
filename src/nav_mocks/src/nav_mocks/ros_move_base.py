"""move_base mock node: actionlib `move_base` (MoveBaseAction), /move_base_simple/goal, plan,
make_plan, /cmd_vel, /diagnostics. The work is done by nav_mocks.move_base_core each cycle.

Callbacks only cache under the lock; the control timer (~controller_frequency) takes new goals,
cancels, the latest scan and the robot pose (tf global_frame -> base_frame) and runs the core.

Every timer, subscriber, action server callback and the make_plan service run under one
supervision.ros_supervisor.Supervisor ("nav_mocks: move_base: supervision"): a fault in the
control cycle stops the robot (a zero /cmd_vel), aborts the active goal with the reason and ends
every goal the cycle had taken; the next cycle runs as usual.
"""
import threading
import time
from dataclasses import dataclass

import actionlib
import rospy
import tf2_ros
from actionlib_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseStamped, Twist
from move_base_msgs.msg import (MoveBaseAction, MoveBaseActionGoal, MoveBaseFeedback,
                                MoveBaseResult)
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from nav_msgs.srv import GetPlan, GetPlanResponse
from sensor_msgs.msg import LaserScan

from nav_mocks.conversions import (map_from_msg, path_to_msg, pose_from_msg, pose_from_transform,
                                   pose_to_msg, scan_from_msg)
from nav_mocks.costmap import Costmap, CostmapConfig
from nav_mocks.dwa import DwaConfig
from nav_mocks.global_planner import NoPath, PlannerConfig
from nav_mocks.move_base_core import (ABORTED, ACTIVE, PREEMPTED, REJECTED, SUCCEEDED,
                                      MoveBaseConfig, MoveBaseCore)
from nav_mocks.param_checks import positive_number
from nav_mocks.pose2d import compose
from supervision.health import fault_text
from supervision.ros_params import config_from_params, refuse_unknown_params
from supervision.ros_supervisor import Supervisor

# goal states actionlib lets a server cancel (else it logs an ERROR)
CANCELLABLE = (GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.RECALLING, GoalStatus.PREEMPTING)
TF_ERRORS = (tf2_ros.LookupException, tf2_ros.ConnectivityException,
             tf2_ros.ExtrapolationException)


@dataclass(frozen=True)
class MoveBaseNodeParams:
    """~parameters of the node besides MoveBaseConfig's and its sub-namespaces'."""

    global_frame: str = "map"
    robot_base_frame: str = "base_link"
    controller_frequency: float = 10.0  # [Hz]


class MoveBaseNode:
    def __init__(self):
        params = config_from_params(MoveBaseNodeParams)
        self.global_frame = params.global_frame
        self.base_frame = params.robot_base_frame
        self.period = 1.0 / positive_number(   # [s]
            rospy.resolve_name("~controller_frequency"), params.controller_frequency, "Hz")
        self.costmap_config = config_from_params(CostmapConfig, "~costmap")
        self.dwa_config = config_from_params(DwaConfig, "~DWAPlannerROS")
        self.dwa_config.control_period = self.period
        self.config = config_from_params(MoveBaseConfig, "~")
        self.planner_config = config_from_params(PlannerConfig, "~planner")
        refuse_unknown_params({"": (MoveBaseNodeParams, MoveBaseConfig), "costmap": CostmapConfig,
                               "DWAPlannerROS": DwaConfig, "planner": PlannerConfig})
        self.lock = threading.Lock()
        self.map_msg = self.scan = self.odom = None
        self.new_goals, self.cancels = [], []
        self.taken_goals, self.taken_cancels = [], []   # taken by the running cycle, not handled
        self.handle = None            # goal handle being executed
        self.core = None
        self.last_cycle = {"duration": 0.0, "status": "idle"}
        self.goal_note = ""           # how the current (or last) goal was moved off an obstacle
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self.cmd_pub = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        self.plan_pub = rospy.Publisher("~plan", Path, queue_size=1, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.goal_pub = rospy.Publisher("move_base/goal", MoveBaseActionGoal, queue_size=1)
        self.sup = sup = Supervisor("nav_mocks: move_base", hardware_id="move_base_mock")
        sup.subscriber("map", OccupancyGrid, self._cache("map_msg"), queue_size=1)
        sup.subscriber("scan", LaserScan, self._cache("scan"), queue_size=1)
        sup.subscriber("odom", Odometry, self._cache("odom"), queue_size=1)
        sup.subscriber("move_base_simple/goal", PoseStamped, self._on_simple_goal, queue_size=1)
        sup.worker("goal callback")
        sup.worker("cancel callback")
        self.server = actionlib.ActionServer(
            "move_base", MoveBaseAction, sup.wrap("goal callback", self._on_goal),
            sup.wrap("cancel callback", self._on_cancel), auto_start=False)
        sup.service("~make_plan", GetPlan, self._make_plan)
        rospy.on_shutdown(self._stop)
        self.server_started = False   # as move_base: serve goals once there is a map and a pose
        sup.timer(self.period, self._cycle, worker="control", on_error=self._cycle_failed)
        sup.timer(1.0, self._diagnose, worker="diagnostics")

    # callbacks: cache only -----------------------------------------------------------------------
    def _cache(self, name):
        def store(msg):
            with self.lock:
                setattr(self, name, msg)
        return store

    def _on_goal(self, handle):
        with self.lock:
            self.new_goals.append(handle)

    def _on_cancel(self, handle):
        with self.lock:
            self.cancels.append(handle)

    def _on_simple_goal(self, msg):
        """As move_base: a /move_base_simple/goal becomes a goal of its own action server."""
        action_goal = MoveBaseActionGoal()
        action_goal.header.stamp = rospy.Time.now()
        action_goal.goal.target_pose = msg
        self.goal_pub.publish(action_goal)

    # helpers -------------------------------------------------------------------------------------
    def _lookup(self, frame):
        """Latest pose (x, y, yaw) of `frame` in the global frame."""
        tf = self.tf_buffer.lookup_transform(self.global_frame, frame.lstrip("/"), rospy.Time(0),
                                             rospy.Duration(0.05))
        return pose_from_transform(tf.transform)

    def _scan_pose(self, scan, odom_frame):
        """Laser pose (x, y, yaw) in the global frame when `scan` was taken.

        odom -> laser at the scan's stamp, map -> odom at the latest (tf2 time travel through
        the odom frame): odometry is exact between the two times and AMCL's correction changes
        slowly. costmap_2d waits for map -> odom at the stamp; a mock AMCL late under load
        would leave only the latest laser pose, which lays an older scan of a turning robot
        down turned and marks walls in free space. A TF error (no odometry at the stamp)
        drops the scan, as costmap_2d's message filter does."""
        tf = self.tf_buffer.lookup_transform_full(
            self.global_frame, rospy.Time(0), scan.header.frame_id.lstrip("/"),
            scan.header.stamp, odom_frame, rospy.Duration(0.05))
        return pose_from_transform(tf.transform)

    def _goal_in_global(self, target):
        """PoseStamped -> (x, y, yaw) in the global frame; ValueError names the problem."""
        frame = target.header.frame_id.lstrip("/")
        pose = pose_from_msg(target.pose)
        if frame in ("", self.global_frame):
            return pose
        try:
            return compose(self._lookup(frame), pose)
        except TF_ERRORS as error:
            raise ValueError(f"cannot transform the goal from {frame!r}: {error}") from error

    def _update_map(self, map_msg):
        try:
            grid = map_from_msg(map_msg)
        except ValueError as error:
            rospy.logwarn_throttle(10.0, "move_base mock: bad /map: %s", error)
            return
        if self.core is None:
            self.core = MoveBaseCore(Costmap(grid, self.costmap_config), self.config,
                                     self.dwa_config, self.planner_config)
            rospy.loginfo("move_base mock: map %dx%d received", grid.width, grid.height)
        else:
            self.core.costmap.set_static(grid)

    def _publish_cmd(self, cmd):
        twist = Twist()
        twist.linear.x, twist.linear.y, twist.angular.z = cmd
        self.cmd_pub.publish(twist)

    def _stop(self):
        self._publish_cmd((0.0, 0.0, 0.0))

    # the control cycle ---------------------------------------------------------------------------
    def _cycle(self, _event):
        started = time.perf_counter()
        with self.lock:
            map_msg, self.map_msg = self.map_msg, None
            scan, self.scan = self.scan, None
            odom = self.odom
            self.taken_goals, self.new_goals = self.new_goals, []
            self.taken_cancels, self.cancels = self.cancels, []
        if map_msg is not None:
            self._update_map(map_msg)
        self._handle_cancels()
        pose = self._robot_pose()
        if not self.server_started and self.core is not None and pose is not None:
            self.server.start()       # clients wait_for_server until then
            self.server_started = True
            rospy.loginfo("move_base mock: map and robot pose available, action server started")
        while self.taken_goals:
            self._handle_new_goal(self.taken_goals[0], pose)
            self.taken_goals.pop(0)
        if self.core is None or pose is None or self.handle is None:
            return
        if scan is not None and odom is not None:
            try:
                self.core.observe(scan_from_msg(scan),
                                  self._scan_pose(scan, odom.header.frame_id.lstrip("/")))
            except TF_ERRORS as error:
                rospy.logwarn_throttle(10.0, "move_base mock: scan not placed: %s", error)
        velocity = (0.0, 0.0, 0.0)
        if odom is not None:
            twist = odom.twist.twist
            velocity = (twist.linear.x, twist.linear.y, twist.angular.z)
        result = self.core.step(rospy.get_time(), pose, velocity)
        self._publish_cmd(result.cmd)
        if result.new_plan is not None:
            self.plan_pub.publish(path_to_msg(result.new_plan.points, self.global_frame,
                                              rospy.Time.now(), self.core.run.goal[2]))
        self._report(result, pose)
        self.last_cycle = {"duration": time.perf_counter() - started, "status": result.status}

    def _robot_pose(self):
        try:
            return self._lookup(self.base_frame)
        except TF_ERRORS as error:
            rospy.logwarn_throttle(10.0, "move_base mock: no robot pose: %s", error)
            return None

    def _handle_cancels(self):
        while self.taken_cancels:
            handle = self.taken_cancels[0]
            if self.handle is not None and handle.get_goal_id().id == self.handle.get_goal_id().id:
                self.core.cancel("cancelled")
                self._stop()
                self.handle = None
            if handle.get_goal_status().status in CANCELLABLE:   # not one that ended while
                handle.set_canceled(MoveBaseResult(), "cancelled")   # the cancel was on its way
            self.taken_cancels.pop(0)

    def _cycle_failed(self, error):
        """The control cycle raised: stop the robot, abort the active goal with the reason, end
        the goals and cancels the cycle had taken; the next cycle runs as usual."""
        self._stop()
        reason = f"move_base mock: control cycle failed: {fault_text(error)}"
        rospy.logerr("%s; robot stopped", reason)
        handle, self.handle = self.handle, None
        ended = [] if handle is None else [handle]
        ended += [h for h in self.taken_goals + self.taken_cancels if h is not handle]
        self.taken_goals, self.taken_cancels = [], []
        for goal in ended:
            self._end(goal, reason)
        if self.core is not None:
            self.core.cancel(reason)

    @staticmethod
    def _end(handle, reason):
        """Abort (active) or reject (pending) a goal; one already ended stays as it is."""
        status = handle.get_goal_status().status
        if status in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING):
            handle.set_aborted(MoveBaseResult(), reason)
        elif status in (GoalStatus.PENDING, GoalStatus.RECALLING):
            handle.set_rejected(MoveBaseResult(), reason)

    def _handle_new_goal(self, handle, pose):
        if handle.get_goal_status().status in (GoalStatus.RECALLING, GoalStatus.RECALLED):
            return   # cancelled before this cycle picked it up
        reason = ""
        try:
            goal = self._goal_in_global(handle.get_goal().target_pose)
        except ValueError as error:
            reason = str(error)
        if not reason and (self.core is None or pose is None):
            reason = "no map yet" if self.core is None else "no robot pose (tf) yet"
        status = REJECTED
        if not reason:
            status, reason = self.core.start_goal(goal, rospy.get_time(), pose)
        if status == REJECTED:
            rospy.logwarn("move_base mock: goal rejected: %s", reason)
            handle.set_rejected(MoveBaseResult(), reason)
            return
        if self.handle is not None:
            self.handle.set_canceled(MoveBaseResult(), "preempted by a new goal")
        self.handle = handle
        self.goal_note = reason
        handle.set_accepted(f"accepted; {reason}" if reason else "accepted")
        rospy.loginfo("move_base mock: new goal (%.2f, %.2f, %.2f)", *goal)
        if reason:
            rospy.logwarn("move_base mock: %s", reason)

    def _report(self, result, pose):
        if result.goal_note != self.goal_note:
            self.goal_note = result.goal_note
            rospy.logwarn("move_base mock: %s", result.goal_note or "goal free again: driving "
                          "to the goal as requested")
        if result.status == ACTIVE:
            feedback = MoveBaseFeedback()
            feedback.base_position.header.stamp = rospy.Time.now()
            feedback.base_position.header.frame_id = self.global_frame
            pose_to_msg(pose, feedback.base_position.pose)
            self.handle.publish_feedback(feedback)
            return
        if result.status == SUCCEEDED:
            self.handle.set_succeeded(MoveBaseResult(), "goal reached" + (
                f"; {result.goal_note}" if result.goal_note else ""))
        elif result.status == ABORTED:
            rospy.logwarn("move_base mock: goal aborted: %s", result.reason)
            self.handle.set_aborted(MoveBaseResult(), result.reason)
        elif result.status == PREEMPTED:
            self.handle.set_canceled(MoveBaseResult(), result.reason)
        self.handle = None

    # make_plan service and diagnostics ------------------------------------------------------------
    def _make_plan(self, request):
        """nav_msgs/GetPlan: an empty path when no plan exists (as move_base replies); a
        blocked or unreachable goal is moved to the nearest free cell within `tolerance`."""
        response = GetPlanResponse()
        response.plan.header.frame_id = self.global_frame
        response.plan.header.stamp = rospy.Time.now()
        if self.core is None:
            rospy.logwarn("move_base mock: make_plan before a map arrived")
            return response
        try:
            start = self._goal_in_global(request.start)
            goal = self._goal_in_global(request.goal)
            plan = self.core.make_plan(start, goal, float(request.tolerance))
        except (ValueError, NoPath) as error:
            rospy.logwarn("move_base mock: make_plan: %s", error)
            return response
        response.plan = path_to_msg(plan.points, self.global_frame, rospy.Time.now(), goal[2])
        return response

    def _diagnose(self, _event):
        names = {ACTIVE: "active", SUCCEEDED: "succeeded", ABORTED: "aborted",
                 PREEMPTED: "preempted", GoalStatus.PENDING: "idle"}
        if self.core is None:
            level, message = DiagnosticStatus.WARN, "waiting for /map"
        elif self.last_cycle["duration"] > self.period:
            level, message = DiagnosticStatus.WARN, "control cycle slower than its period"
        else:
            level, message = DiagnosticStatus.OK, names.get(self.last_cycle["status"], "idle")
            if self.goal_note:
                message += f"; {self.goal_note}"
        status = DiagnosticStatus(level=level, name="nav_mocks: move_base",
                                  hardware_id="move_base_mock", message=message)
        status.values = [KeyValue("cycle_ms", f"{1e3 * self.last_cycle['duration']:.1f}"),
                         KeyValue("goal_active", str(self.handle is not None)),
                         KeyValue("goal_moved", self.goal_note)]
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diag_pub.publish(array)


def main(_argv):
    rospy.init_node("move_base")
    try:
        MoveBaseNode()
    except ValueError as error:
        rospy.logfatal("move_base mock: %s", error)
        return 1
    rospy.spin()
    return 0
