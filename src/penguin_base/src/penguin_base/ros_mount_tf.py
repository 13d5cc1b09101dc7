"""ROS node `mount_tf`: a static transform of a sensor mount (e.g. base_link -> base_laser).

Reads the mount from the private parameter dictionary named by ~section (default `laser_mount`,
as in config/penguin.yaml).
"""
import time

import rospy
import tf2_ros

from penguin_base.conversions import transform_msg

MOUNT_KEYS = ("parent_frame", "child_frame", "x", "y", "z", "yaw")


def read_mount(values, section):
    """Validate a mount dictionary; returns (parent, child, x, y, z, yaw)."""
    unknown = sorted(set(values) - set(MOUNT_KEYS))
    if unknown:
        raise ValueError(f"~{section}: unknown key(s) {unknown}; known: {list(MOUNT_KEYS)}")
    try:
        offsets = [float(values.get(k, 0.0)) for k in ("x", "y", "z", "yaw")]
    except (TypeError, ValueError) as error:
        raise ValueError(f"~{section}: x, y, z and yaw must be numbers ({error})") from None
    return (str(values.get("parent_frame", "base_link")),
            str(values.get("child_frame", "base_laser")), *offsets)


def main():
    rospy.init_node("mount_tf")
    section = rospy.get_param("~section", "laser_mount")
    try:
        parent, child, x, y, z, yaw = read_mount(rospy.get_param(f"~{section}", {}), section)
    except ValueError as error:
        rospy.logfatal("mount_tf: %s", error)
        return 2
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    broadcaster.sendTransform(transform_msg(rospy.Time.now(), parent, child, x, y, z, yaw))
    rospy.loginfo("mount_tf: %s -> %s at (%.3f, %.3f, %.3f) m, yaw %.3f rad",
                  parent, child, x, y, z, yaw)
    while not rospy.is_shutdown():
        time.sleep(0.2)
    return 0
