"""Messages <-> core types for penguin_base."""
import math

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Quaternion, TransformStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState


def yaw_quaternion(yaw):
    """Quaternion of a rotation about z by yaw [rad]."""
    return Quaternion(x=0.0, y=0.0, z=math.sin(0.5 * yaw), w=math.cos(0.5 * yaw))


def twist_msg(v, omega):
    msg = Twist()
    msg.linear.x, msg.angular.z = float(v), float(omega)
    return msg


def twist_from_msg(msg):
    """(v, omega) of a Twist; a differential drive ignores the other components."""
    return msg.linear.x, msg.angular.z


def wheel_command_msg(stamp, joint_names, left, right):
    """Wheel velocity command [rad/s] as a JointState (velocity field only)."""
    msg = JointState()
    msg.header.stamp = stamp
    msg.name = list(joint_names)
    msg.velocity = [float(left), float(right)]
    return msg


def wheel_angles_from_msg(msg, joint_names):
    """(stamp [s], left angle, right angle) [rad] of a wheel encoder JointState.

    Raises ValueError naming what is missing.
    """
    angles = []
    for joint in joint_names:
        if joint not in msg.name:
            raise ValueError(f"wheel encoder state has no joint {joint!r} (names: {msg.name})")
        index = msg.name.index(joint)
        if index >= len(msg.position):
            raise ValueError(f"wheel encoder state has no position for joint {joint!r}")
        angles.append(msg.position[index])
    return msg.header.stamp.to_sec(), angles[0], angles[1]


def odometry_msg(state, stamp, odom_frame, base_frame):
    """nav_msgs/Odometry of an OdometryState."""
    msg = Odometry()
    msg.header.stamp = stamp
    msg.header.frame_id = odom_frame
    msg.child_frame_id = base_frame
    msg.pose.pose.position.x, msg.pose.pose.position.y = state.x, state.y
    msg.pose.pose.orientation = yaw_quaternion(state.theta)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = state.v, state.omega
    return msg


def transform_msg(stamp, parent, child, x, y, z, yaw):
    msg = TransformStamped()
    msg.header.stamp = stamp
    msg.header.frame_id, msg.child_frame_id = parent, child
    msg.transform.translation.x = x
    msg.transform.translation.y = y
    msg.transform.translation.z = z
    msg.transform.rotation = yaw_quaternion(yaw)
    return msg


def diagnostics_msg(stamp, name, hardware_id, level, message, values):
    """A DiagnosticArray with one status."""
    status = DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                              values=[KeyValue(key=k, value=v) for k, v in values.items()])
    array = DiagnosticArray(status=[status])
    array.header.stamp = stamp
    return array
