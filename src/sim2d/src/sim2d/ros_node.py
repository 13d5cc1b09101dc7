"""ROS node around sim2d.World: sim-time clock, lasers, odometry, tf, wheels, camera, markers.

Callbacks only cache commands under a lock; one loop thread steps the world at `~step` seconds
of sim time, paced to `~speed` x real time by the wall clock, and publishes what is due.

Subscribers, the door service and every pass of the loop run under one
supervision.ros_supervisor.Supervisor: a pass that raises is logged once and skipped (the loop
goes on), and "sim2d: sim2d: supervision" on /diagnostics is ERROR meanwhile, or when the loop
stops beating.
"""
import math
import threading
import time
import warnings
from dataclasses import dataclass, field

import rospy
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState, LaserScan
from std_msgs.msg import Bool
from tamp_msgs.msg import PerceptionFrame
from tamp_msgs.srv import SetDoor, SetDoorResponse
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray

from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor

from sim2d import conversions
from sim2d.kinematics import DIFFERENTIAL, twist_to_wheels
from sim2d.pacing import Pacer, PacerConfig
from sim2d.world import CACHE_DIR, CommandError, World

def in_loop_publisher(topic, msg_type):
    """A publisher the loop feeds every step, writing in the loop's thread (queue_size None).
    A queue hands each message to a thread per subscriber and yields after every one (rospy's
    QueuedConnection); at 50x real time those thread switches halved the node's speed.
    Subscribers read on threads of their own, so a write waits only on a frozen subscriber, and
    the supervision status then shows the loop not beating."""
    with warnings.catch_warnings():   # rospy warns that queue_size None is synchronous
        warnings.simplefilter("ignore", SyntaxWarning)
        return rospy.Publisher(topic, msg_type, queue_size=None)


@dataclass
class NodeConfig:
    """~parameters of the node (all times in sim seconds)."""

    world: str = ""                 # world YAML (required)
    laser_dir: str = ""             # laser models; "" = tamp_resources' config/lasers
    raycast: str = ""               # "" = as the world says; "march" or "table" for all lasers
    lazy_tables: bool = True        # a range table not yet cached fills its rows as the lasers
                                    # need them (starts at once); false: tabulate the whole map
                                    # first and cache it
    speed: float = 1.0              # [-] sim seconds per wall second; <= 0: as fast as possible
    step: float = 0.005             # [s] integration step
    odom_rate: float = 50.0         # [Hz] /odom, tf, ground truth, joint_states
    clock_rate: float = 50.0        # [Hz] /clock at least this often, and before every other
                                    # message, so no stamp is ahead of the clock
    marker_rate: float = 2.0        # [Hz]
    diagnostics_rate: float = 1.0   # [Hz]
    cmd_timeout: float = 0.5        # [s] stop a robot whose last command is older than this
    publish_map_odom: bool = False  # also publish map -> odom from ground truth (no AMCL)
    diff_drive_cmd_vel: bool = False  # differential robots also obey cmd_vel (no penguin_base)
    diff_drive_odom: bool = True    # differential robots: publish odom + odom -> base_link; false
                                    # when penguin_base computes them from the wheel encoders


def read_config():
    return config_from_params(NodeConfig)


@dataclass
class RobotIO:
    """Publishers, subscribers and cached commands of one simulated robot."""

    robot: object
    prefix: str                      # "" or "<namespace>/"
    scans: list = field(default_factory=list)    # [(publisher, frame_id, last count)]
    command: tuple = None            # ("twist", vx, vy, wz) or ("wheels", left, right)
    command_time: float = -1e9       # [s] sim time of the last command
    stalled: bool = None             # last published on `stall` (latched: sent on change)


class SimNode:
    def __init__(self):
        self.config = read_config()
        self.lock = threading.Lock()
        self.world = None
        self.io = []
        self.door_changes = []   # [(name, closed)] requested, applied by the loop
        self.last = {}
        self.started_wall = None
        self.pacer = None
        self.sup = None

    def setup(self, sup=None):
        """Load the world and create the ROS interfaces under the node's Supervisor `sup` (one
        is made when None); False (with a log line) on bad input."""
        self.sup = sup or Supervisor("sim2d: sim2d", hardware_id="sim2d")
        if not self.config.world:
            rospy.logfatal("sim2d: parameter ~world (path of a world YAML) is required")
            return False
        rospy.loginfo("sim2d: loading %s (range tables cached in %s are loaded; %s)",
                      self.config.world, CACHE_DIR,
                      "others fill as the lasers need them" if self.config.lazy_tables
                      else "others are built for the whole map first")
        try:
            self.world = World.from_file(self.config.world, self.config.laser_dir or None,
                                         raycast=self.config.raycast or None,
                                         lazy_tables=self.config.lazy_tables)
        except (ValueError, OSError) as error:
            rospy.logfatal("sim2d: cannot load world: %s", error)
            return False
        if not (self.config.step > 0):
            rospy.logfatal("sim2d: ~step must be > 0, got %s", self.config.step)
            return False
        self.clock_pub = in_loop_publisher("/clock", Clock)
        self.marker_pub = rospy.Publisher("sim2d/markers", MarkerArray, queue_size=1, latch=True)
        self.object_markers = conversions.ObjectMarkers()
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        self.tf_pub = in_loop_publisher("/tf", TFMessage)
        self.static_tf = tf2_ros.StaticTransformBroadcaster()
        statics = []
        for robot in self.world.robots:
            io = RobotIO(robot, f"{robot.config.namespace}/" if robot.config.namespace else "")
            self._make_interfaces(io)
            statics += self._static_transforms(io)
            self.io.append(io)
        self.static_tf.sendTransform(statics)
        self.sup.service("~set_door", SetDoor, self._on_set_door, worker="set_door service")
        return True

    def frame(self, io, name):
        return name if name.startswith(io.prefix) else io.prefix + name

    def _make_interfaces(self, io):
        rc, p = io.robot.config, io.prefix
        for mount in io.robot.laser_mounts:
            io.scans.append([in_loop_publisher(p + mount.topic, LaserScan),
                             self.frame(io, mount.frame), 0])
        io.odom_pub = in_loop_publisher(p + "odom", Odometry)
        io.truth_pub = in_loop_publisher(p + "base_pose_ground_truth", Odometry)
        io.stall_pub = rospy.Publisher(p + "stall", Bool, queue_size=1, latch=True)
        if rc.drive != DIFFERENTIAL or self.config.diff_drive_cmd_vel:
            self.sup.subscriber(p + "cmd_vel", Twist, lambda msg, io=io: self._on_twist(msg, io),
                                queue_size=1)
        if rc.drive == DIFFERENTIAL:
            self.sup.subscriber(p + "wheel_command", JointState,
                                lambda msg, io=io: self._on_wheels(msg, io), queue_size=1)
            io.joint_pub = in_loop_publisher(p + "joint_states", JointState)
        if io.robot.camera is not None:
            io.camera_pub = in_loop_publisher(p + "camera/detections", PerceptionFrame)

    def _static_transforms(self, io):
        base = self.frame(io, "base_link")
        out = [conversions.transform_msg(0.0, base, self.frame(io, m.frame), m.mount[0],
                                         m.mount[1], m.mount_height, yaw=m.mount[2])
               for m in io.robot.laser_mounts]
        rig = io.robot.config.camera
        if rig is not None:
            for name, cam in (("camera_top", rig.top), ("camera_bottom", rig.bottom)):
                out.append(conversions.transform_msg(0.0, base, self.frame(io, name),
                                                     cam.mount_x, 0.0, cam.mount_height,
                                                     pitch=cam.tilt))
                # REP 103 optical frame: z forward, x right, y down
                out.append(conversions.transform_msg(0.0, self.frame(io, name),
                                                     self.frame(io, name + "_optical"), 0.0, 0.0,
                                                     0.0, roll=-math.pi / 2, yaw=-math.pi / 2))
        return out

    # --- callbacks: cache only -----------------------------------------------------------
    def _on_twist(self, msg, io):
        command = conversions.twist_command(msg)
        if not all(math.isfinite(v) for v in command):
            rospy.logwarn_throttle(5.0, "sim2d: %s: rejected non-finite cmd_vel %s",
                                   io.robot.name, command)
            return
        with self.lock:
            io.command, io.command_time = ("twist",) + command, self.world.time

    def _on_wheels(self, msg, io):
        try:
            command = conversions.wheel_command(msg)
        except ValueError as error:
            rospy.logwarn_throttle(5.0, "sim2d: %s: rejected wheel command: %s",
                                   io.robot.name, error)
            return
        if not all(math.isfinite(v) for v in command):
            rospy.logwarn_throttle(5.0, "sim2d: %s: rejected non-finite wheel command %s",
                                   io.robot.name, command)
            return
        with self.lock:
            io.command, io.command_time = ("wheels",) + command, self.world.time

    def _on_set_door(self, request):
        if request.name not in self.world.doors:
            known = ", ".join(sorted(self.world.doors)) or "none"
            return SetDoorResponse(False, f"no door named {request.name!r} (doors: {known})")
        with self.lock:
            self.door_changes.append((request.name, bool(request.closed)))
        state = "closed" if request.closed else "open"
        rospy.loginfo("sim2d: door %s %s", request.name, state)
        return SetDoorResponse(True, f"door {request.name} {state}")

    # --- loop ----------------------------------------------------------------------------
    def _apply_commands(self):
        with self.lock:
            for name, closed in self.door_changes:
                self.world.set_door(name, closed)
            self.door_changes = []
            for io in self.io:
                name = io.robot.name
                fresh = self.world.time - io.command_time <= self.config.cmd_timeout
                try:
                    if io.command is None or not fresh:
                        if io.robot.config.drive == DIFFERENTIAL:
                            self.world.set_wheel_speeds(name, 0.0, 0.0)
                        else:
                            self.world.set_twist(name, 0.0, 0.0, 0.0)
                    elif io.command[0] == "wheels":
                        self.world.set_wheel_speeds(name, *io.command[1:])
                    else:
                        self.world.set_twist(name, *io.command[1:])
                except CommandError as error:
                    rospy.logwarn_throttle(5.0, "sim2d: rejected command: %s", error)
                    io.command = None

    def _due(self, key, rate):
        if rate <= 0:
            return False
        if self.world.time + 1e-9 >= self.last.get(key, 0.0):
            self.last[key] = self.last.get(key, 0.0) + 1.0 / rate
            return True
        return False

    def _publish(self):
        """Publish what is due at this step. /clock goes out at ~clock_rate and before any other
        message, not every step: at 200 steps/s every node's /clock callback cost more than the
        simulation (a profile spent 7.3 s of 20 s yielding after /clock messages)."""
        now = self.world.time
        clock_due = self._due("clock", self.config.clock_rate)
        odom_due = self._due("odom", self.config.odom_rate)
        cameras = [io for io in self.io if io.robot.config.camera is not None
                   and self._due(("camera", io.robot.name), io.robot.config.camera.rate)]
        markers_due = self._due("markers", self.config.marker_rate)
        diagnostics_due = self._due("diagnostics", self.config.diagnostics_rate)
        new_scans = [self._new_scans(io) for io in self.io]
        if clock_due or odom_due or cameras or markers_due or diagnostics_due or any(new_scans):
            self.clock_pub.publish(Clock(clock=conversions.stamp(now)))
        for io, scans in zip(self.io, new_scans):
            self._publish_scans(io, scans)
            if odom_due:
                self._publish_odometry(io, now)
            if io in cameras:
                frame = self.world.camera_frame(io.robot.name)
                io.camera_pub.publish(conversions.frame_msg(
                    frame, now, self.frame(io, "camera_top_optical")))
        if markers_due:
            self.marker_pub.publish(MarkerArray(
                markers=conversions.people_markers(now, self.world.people)
                + self.object_markers.update(now, list(self.world.objects.values()))))
        if diagnostics_due:
            self._publish_diagnostics(now)

    @staticmethod
    def _new_scans(io):
        """The indices of the robot's lasers with a scan not yet published."""
        return [j for j, entry in enumerate(io.scans)
                if io.robot.scans[j] is not None and io.robot.scans[j].count != entry[2]]

    def _publish_scans(self, io, new_scans):
        for j in new_scans:
            entry, scan = io.scans[j], io.robot.scans[j]
            entry[2] = scan.count
            entry[0].publish(conversions.scan_msg(scan, io.robot.laser_mounts[j].model, entry[1]))

    def _publish_odometry(self, io, now):
        robot, odom, base = io.robot, self.frame(io, "odom"), self.frame(io, "base_link")
        state = robot.state
        pose = robot.odometry.pose
        io.truth_pub.publish(conversions.odometry_msg(now, "map", base, state.pose, state.twist))
        if robot.config.drive != DIFFERENTIAL or self.config.diff_drive_odom:
            io.odom_pub.publish(conversions.odometry_msg(now, odom, base, pose, state.twist))
            transforms = [conversions.transform_msg(now, odom, base, pose[0], pose[1], 0.0,
                                                    yaw=pose[2])]
            if self.config.publish_map_odom:
                transforms.append(self._map_to_odom(now, odom, state.pose, pose))
            self.tf_pub.publish(TFMessage(transforms))
        if state.stalled != io.stalled:
            io.stall_pub.publish(Bool(data=state.stalled))
            io.stalled = state.stalled
        if robot.config.drive == DIFFERENTIAL:
            wheels = robot.config.wheels
            speeds = twist_to_wheels(state.twist[0], state.twist[2], wheels)
            io.joint_pub.publish(conversions.encoder_msg(now, state.wheel_angles, speeds,
                                                         wheels.encoder_ticks_per_rev))

    @staticmethod
    def _map_to_odom(now, odom_frame, truth, odom):
        """map -> odom such that map -> odom -> base_link equals the ground truth."""
        yaw = truth[2] - odom[2]
        c, s = math.cos(yaw), math.sin(yaw)
        x = truth[0] - (c * odom[0] - s * odom[1])
        y = truth[1] - (s * odom[0] + c * odom[1])
        return conversions.transform_msg(now, "map", odom_frame, x, y, 0.0, yaw=yaw)

    def _publish_diagnostics(self, now):
        wall = time.monotonic() - self.started_wall
        factor = now / wall if wall > 0 else 0.0
        array = DiagnosticArray()
        array.header.stamp = conversions.stamp(now)
        for io in self.io:
            state = io.robot.state
            status = DiagnosticStatus(name=f"sim2d: {io.robot.name}", hardware_id="sim2d")
            status.level = DiagnosticStatus.WARN if state.stalled else DiagnosticStatus.OK
            status.message = "stalled against an obstacle" if state.stalled else "ok"
            status.values = [KeyValue("bumps", str(state.bumps)),
                             KeyValue("real_time_factor", f"{factor:.2f}"),
                             KeyValue("slips", str(self.pacer.slips)),
                             KeyValue("seconds_lost", f"{self.pacer.seconds_lost:.2f}"),
                             KeyValue("closed_doors", ",".join(
                                 n for n, closed in self.world.doors.items() if closed))]
            array.status.append(status)
        self.diag_pub.publish(array)

    def spin(self):
        """Step and publish until shutdown, keeping sim time = speed x wall time (pacing.Pacer:
        no racing to catch up after a stall; a speed it cannot hold is logged once)."""
        self.started_wall = time.monotonic()
        speed, step = self.config.speed, self.config.step
        wall_step = step / speed if speed > 0 else step   # [s] of wall time a paced pass takes
        self.sup.worker("loop", wall_step)
        self.pacer = Pacer(PacerConfig(speed), self.world.time, self.started_wall)
        behind_warned = False
        while not rospy.is_shutdown():
            with self.sup.guard("loop", f"sim time {self.world.time:.3f} s") as failure:
                self._apply_commands()
                self.world.step(step)
                self._publish()
            if failure:
                time.sleep(wall_step)   # a pass that keeps failing must not spin the CPU
                continue
            now = time.monotonic()
            pause = self.pacer.delay(self.world.time, now)
            if pause > 0:
                time.sleep(pause)
            achieved = self.pacer.shortfall(self.world.time, now)
            if achieved is not None and not behind_warned:
                rospy.logwarn("sim2d: cannot keep speed %.1f: %.2f over the last %.0f s of wall "
                              "time", speed, achieved, self.pacer.config.window)
                behind_warned = True
