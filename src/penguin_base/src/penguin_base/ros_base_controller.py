"""ROS node `base_controller`: /cmd_vel -> wheel commands; wheel encoders -> /odom and tf.

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor. A fault in the
control step stops the robot (zero wheel speeds are published and the controller restarts from
rest, `BaseController.halt`): a robot stops when its controller stops. The status
"penguin_base: base_controller: supervision" on /diagnostics is ERROR meanwhile.
"""
import signal
import threading
import time
from dataclasses import dataclass, field

import rospy
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor

from penguin_base.config import BaseConfig
from penguin_base.controller import BaseController
from penguin_base.conversions import (diagnostics_msg, odometry_msg, transform_msg,
                                      twist_from_msg, wheel_angles_from_msg, wheel_command_msg)
from penguin_base.odometry import EncoderError, OdometryIntegrator
from penguin_base.safety import InvalidCommand

ZERO_REPEATS = 3  # zero wheel commands sent on shutdown (one may be lost while connections close)


@dataclass(frozen=True)
class BaseControllerParams:
    """~parameters of the node."""

    base: dict = field(default_factory=dict)  # BaseConfig section (config/penguin.yaml)
    left_joint: str = "left_wheel_joint"
    right_joint: str = "right_wheel_joint"
    odom_frame: str = "odom"
    base_frame: str = "base_link"
    publish_tf: bool = True                   # odom -> base_link on /tf


class BaseControllerNode:
    """Owns the ROS plumbing; the control logic is penguin_base.controller.BaseController."""

    def __init__(self):
        params = config_from_params(BaseControllerParams)
        self.config = BaseConfig.from_dict(params.base)
        self.joints = (params.left_joint, params.right_joint)
        self.odom_frame = params.odom_frame
        self.base_frame = params.base_frame
        self.publish_tf = params.publish_tf
        self.controller = BaseController(self.config)
        self.odometry = OdometryIntegrator(self.config.wheel_radius, self.config.wheel_separation)
        self._lock = threading.Lock()
        self._commands, self._encoders = [], []  # cached under the lock, consumed by the timer
        self._estop = self._bumper = None
        self._published_state = None
        self._timers = []

    def start(self, sup):
        """Create the ROS interfaces under the node's Supervisor `sup`."""
        self.wheel_pub = rospy.Publisher("wheel_command", JointState, queue_size=1)
        self.odom_pub = rospy.Publisher("odom", Odometry, queue_size=5)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.tf_broadcaster = tf2_ros.TransformBroadcaster()
        sup.subscriber(rospy.resolve_name("cmd_vel"), Twist, self._on_cmd_vel, queue_size=10)
        sup.subscriber(rospy.resolve_name("e_stop"), Bool, self._on_estop, queue_size=5)
        sup.subscriber(rospy.resolve_name("bumper"), Bool, self._on_bumper, queue_size=5)
        sup.subscriber(rospy.resolve_name("joint_states"), JointState, self._on_joint_states,
                       queue_size=20)
        self._timers = [
            sup.timer(1.0 / self.config.control_rate, self._control_step, worker="control",
                      on_error=self._stop_on_fault),
            sup.timer(1.0, self._publish_diagnostics, worker="diagnostics")]
        rospy.loginfo("base_controller: wheel radius %.3f m, separation %.3f m, watchdog %.2f s",
                      self.config.wheel_radius, self.config.wheel_separation,
                      self.config.watchdog_timeout)

    def _on_cmd_vel(self, msg):
        with self._lock:
            self._commands.append((rospy.get_time(), *twist_from_msg(msg)))

    def _on_estop(self, msg):
        with self._lock:
            self._estop = msg.data

    def _on_bumper(self, msg):
        with self._lock:
            self._bumper = msg.data

    def _on_joint_states(self, msg):
        with self._lock:
            self._encoders.append(msg)

    def _take_inputs(self):
        with self._lock:
            commands, encoders = self._commands, self._encoders
            self._commands, self._encoders = [], []
            return commands, encoders, self._estop, self._bumper

    def _control_step(self, _event):
        commands, encoders, estop, bumper = self._take_inputs()
        if estop is not None:
            self.controller.set_estop(estop)
        if bumper is not None:
            self.controller.set_bumper(bumper)
        for stamp, v, omega in commands:
            try:
                self.controller.command(v, omega, stamp)
            except InvalidCommand as error:
                rospy.logwarn_throttle(1.0, "base_controller: rejected %s; stopping", error)
        measured = self._integrate(encoders)
        wheels = self.controller.update(rospy.get_time(), measured)
        self.wheel_pub.publish(wheel_command_msg(rospy.Time.now(), self.joints, wheels.left,
                                                 wheels.right))
        self._publish_odometry()

    def _stop_on_fault(self, error):
        """The control step failed: zero wheel speeds now, then restart from rest."""
        self.wheel_pub.publish(wheel_command_msg(rospy.Time.now(), self.joints, 0.0, 0.0))
        self.controller.halt(f"control step failed: {fault_text(error)}", rospy.get_time())

    def _integrate(self, encoders):
        """Odometry from the new encoder readings; returns the measured wheel speeds or None."""
        measured = None
        for msg in encoders:
            try:
                state = self.odometry.update(*wheel_angles_from_msg(msg, self.joints))
                measured = (state.left_speed, state.right_speed)
            except (ValueError, EncoderError) as error:
                rospy.logwarn_throttle(1.0, "base_controller: encoder reading ignored: %s", error)
        return measured

    def _publish_odometry(self):
        state = self.odometry.state
        if not self.odometry.started or state is self._published_state:
            return
        self._published_state = state
        stamp = rospy.Time.from_sec(state.stamp)
        self.odom_pub.publish(odometry_msg(state, stamp, self.odom_frame, self.base_frame))
        if self.publish_tf:
            self.tf_broadcaster.sendTransform(transform_msg(
                stamp, self.odom_frame, self.base_frame, state.x, state.y, 0.0, state.theta))

    def _publish_diagnostics(self, _event):
        level, message, values = self.controller.diagnostics(rospy.get_time())
        self.diag_pub.publish(diagnostics_msg(rospy.Time.now(), "penguin_base: base_controller",
                                              "penguin", level, message, values))

    def shutdown(self):
        """Stop the timers and send zero wheel speeds."""
        for timer in self._timers:
            timer.shutdown()
        for _ in range(ZERO_REPEATS):
            self.wheel_pub.publish(wheel_command_msg(rospy.Time.now(), self.joints, 0.0, 0.0))
            time.sleep(0.05)


def _raise_interrupt(_signum, _frame):
    raise KeyboardInterrupt


def main():
    rospy.init_node("base_controller", disable_signals=True)
    signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        node = BaseControllerNode()
    except ValueError as error:   # a ConfigError, or a parameter of the wrong type
        rospy.logfatal("base_controller: bad configuration: %s", error)
        return 2
    node.start(Supervisor("penguin_base: base_controller", hardware_id="penguin"))
    try:
        while not rospy.is_shutdown():
            time.sleep(0.1)
    except KeyboardInterrupt:
        pass
    finally:
        node.shutdown()
        rospy.signal_shutdown("base_controller exiting")
    return 0
