"""ROS node `mount_tf`: a static transform of a sensor mount (e.g. base_link -> base_laser).

Reads the mount from the private parameter dictionary named by ~section (default `laser_mount`,
as in config/penguin.yaml).
"""
import time
from dataclasses import dataclass, field, make_dataclass

import rospy
import tf2_ros
from supervision.ros_params import config_from_params

from penguin_base.conversions import transform_msg

MOUNT_KEYS = ("parent_frame", "child_frame", "x", "y", "z", "yaw")


@dataclass(frozen=True)
class MountTfParams:
    section: str = "laser_mount"   # the private parameter dictionary that holds the mount


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
    try:
        section = config_from_params(MountTfParams).section
        mount = config_from_params(make_dataclass(  # one dict field named after the section
            "MountParams", [(section, dict, field(default_factory=dict))]))
        parent, child, x, y, z, yaw = read_mount(getattr(mount, section), section)
    except (TypeError, ValueError) as error:   # TypeError: a section that is no identifier
        rospy.logfatal("mount_tf: %s", error)
        return 2
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    broadcaster.sendTransform(transform_msg(rospy.Time.now(), parent, child, x, y, z, yaw))
    rospy.loginfo("mount_tf: %s -> %s at (%.3f, %.3f, %.3f) m, yaw %.3f rad",
                  parent, child, x, y, z, yaw)
    while not rospy.is_shutdown():
        time.sleep(0.2)
    return 0
