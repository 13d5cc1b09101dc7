"""Core types <-> ROS messages for the sim2d node (the only module that knows both)."""
import math

import numpy as np
import rospy
from geometry_msgs.msg import Quaternion, TransformStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState, LaserScan
from tamp_msgs.msg import Detection, PerceptionFrame, Skeleton
from visualization_msgs.msg import Marker

WHEEL_JOINTS = ("left_wheel_joint", "right_wheel_joint")
MARKER_HEIGHT = {"standing": 1.7, "sitting": 1.2, "lying": 0.3}   # [m] person cylinders
# labels: text height [m] (rviz's top-down household view draws about 60 px per metre) and a
# near-black colour that reads on the light floor of the map and on the orange object boxes
PERSON_LABEL_SIZE, OBJECT_LABEL_SIZE = 0.26, 0.2
LABEL_RGBA = (0.05, 0.05, 0.1, 1.0)


def stamp(seconds):
    return rospy.Time.from_sec(seconds)


def yaw_quaternion(yaw):
    return Quaternion(0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def rpy_quaternion(roll, pitch, yaw):
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return Quaternion(sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                      cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def scan_msg(scan, model, frame_id):
    """sim2d Scan + LaserModel -> sensor_msgs/LaserScan (out of range = +inf, REP 117)."""
    msg = LaserScan()
    msg.header.stamp = stamp(scan.stamp)
    msg.header.frame_id = frame_id
    msg.angle_min, msg.angle_max = model.angle_min, model.angle_max
    msg.angle_increment = model.angle_increment
    msg.time_increment = model.scan_time / (2.0 * math.pi / model.angle_increment)
    msg.scan_time = model.scan_time
    msg.range_min, msg.range_max = model.range_min, model.range_max
    msg.ranges = scan.ranges.tolist()
    return msg


def odometry_msg(seconds, frame_id, child_frame_id, pose, twist):
    """(x, y, yaw) + body twist (vx, vy, wz) -> nav_msgs/Odometry."""
    msg = Odometry()
    msg.header.stamp = stamp(seconds)
    msg.header.frame_id = frame_id
    msg.child_frame_id = child_frame_id
    msg.pose.pose.position.x, msg.pose.pose.position.y = pose[0], pose[1]
    msg.pose.pose.orientation = yaw_quaternion(pose[2])
    msg.twist.twist.linear.x, msg.twist.twist.linear.y = twist[0], twist[1]
    msg.twist.twist.angular.z = twist[2]
    return msg


def transform_msg(seconds, parent, child, x, y, z, roll=0.0, pitch=0.0, yaw=0.0):
    msg = TransformStamped()
    msg.header.stamp = stamp(seconds)
    msg.header.frame_id, msg.child_frame_id = parent, child
    msg.transform.translation.x, msg.transform.translation.y = x, y
    msg.transform.translation.z = z
    msg.transform.rotation = rpy_quaternion(roll, pitch, yaw)
    return msg


def twist_command(msg: Twist):
    return msg.linear.x, msg.linear.y, msg.angular.z


def wheel_command(msg: JointState):
    """sensor_msgs/JointState velocities -> (left, right) [rad/s]; ValueError names the problem."""
    if list(msg.name) == list(WHEEL_JOINTS) and len(msg.velocity) == 2:
        return float(msg.velocity[0]), float(msg.velocity[1])
    if len(msg.name) == 0 and len(msg.velocity) == 2:
        return float(msg.velocity[0]), float(msg.velocity[1])
    if set(msg.name) == set(WHEEL_JOINTS) and len(msg.velocity) == 2:
        by_name = dict(zip(msg.name, msg.velocity))
        return float(by_name[WHEEL_JOINTS[0]]), float(by_name[WHEEL_JOINTS[1]])
    raise ValueError(f"wheel command needs velocity for {WHEEL_JOINTS}, got names "
                     f"{list(msg.name)} and {len(msg.velocity)} velocities")


def encoder_msg(seconds, wheel_angles, wheel_speeds, ticks_per_rev):
    """Wheel encoder state: positions quantised to whole ticks [rad], velocities [rad/s]."""
    tick = 2.0 * math.pi / ticks_per_rev
    msg = JointState()
    msg.header.stamp = stamp(seconds)
    msg.name = list(WHEEL_JOINTS)
    msg.position = [math.floor(a / tick) * tick for a in wheel_angles]
    msg.velocity = list(wheel_speeds)
    return msg


def frame_msg(frame, seconds, frame_id):
    """sim2d CameraFrame -> tamp_msgs/PerceptionFrame."""
    msg = PerceptionFrame()
    msg.header.stamp = stamp(seconds)
    msg.header.frame_id = frame_id
    msg.image_width, msg.image_height = frame.width, frame.height
    for det in frame.objects:
        msg.objects.append(Detection(label=det.label, confidence=det.confidence, x=det.x,
                                     y=det.y, width=det.width, height=det.height,
                                     depth=det.depth))
    for sk in frame.skeletons:
        msg.skeletons.append(Skeleton(x=sk.x.astype(float).tolist(), y=sk.y.astype(float).tolist(),
                                      confidence=sk.confidence.astype(float).tolist(),
                                      depth=np.asarray(sk.depth, dtype=float).tolist(),
                                      joint_rgb=sk.joint_colours.ravel().tolist()))
    return msg


def _marker(seconds, ns, ident, kind, x, y, z, size, rgba, yaw=0.0, text=""):
    marker = Marker()
    marker.header.stamp = stamp(seconds)
    marker.header.frame_id = "map"
    marker.ns, marker.id, marker.type, marker.action = ns, ident, kind, Marker.ADD
    marker.pose.position.x, marker.pose.position.y, marker.pose.position.z = x, y, z
    marker.pose.orientation = yaw_quaternion(yaw)
    marker.scale.x, marker.scale.y, marker.scale.z = size
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = rgba
    marker.text = text
    marker.lifetime = rospy.Duration(0)
    return marker


def people_markers(seconds, people):
    """A cylinder in the shirt colour and a label (name, posture, activity) per person."""
    markers = []
    for i, person in enumerate(people):
        height = MARKER_HEIGHT[person.posture]
        r, g, b = (c / 255.0 for c in person.shirt_colour[0])
        x, y, _ = person.pose
        markers.append(_marker(seconds, "people", i, Marker.CYLINDER, x, y, height / 2.0,
                               (2 * person.radius, 2 * person.radius, height), (r, g, b, 0.8)))
        markers.append(_marker(seconds, "people_labels", i, Marker.TEXT_VIEW_FACING, x, y,
                               height + 0.25, (0.0, 0.0, PERSON_LABEL_SIZE), LABEL_RGBA,
                               text=f"{person.name}: {person.posture}, {person.activity}"))
    return markers


def object_markers(seconds, objects, first_id=0):
    """A box per object, labelled with its COCO class (marker ids from `first_id`)."""
    markers = []
    for i, obj in enumerate(objects, start=first_id):
        x, y, yaw = obj.pose
        markers.append(_marker(seconds, "objects", i, Marker.CUBE, x, y,
                               obj.elevation + obj.size[2] / 2.0, obj.size,
                               (0.9, 0.6, 0.2, 0.8), yaw))
        markers.append(_marker(seconds, "object_labels", i, Marker.TEXT_VIEW_FACING, x, y,
                               obj.elevation + obj.size[2] + 0.1, (0.0, 0.0, OBJECT_LABEL_SIZE),
                               LABEL_RGBA, text=obj.label))
    return markers


class ObjectMarkers:
    """object_markers, rebuilt only for objects that moved or changed (most stand still:
    rebuilding 32 objects' markers twice a sim second cost more than the household's physics)."""

    def __init__(self):
        self.cache = {}   # index -> (key, [box, label])

    def update(self, seconds, objects):
        now = stamp(seconds)
        markers = []
        for i, obj in enumerate(objects):
            key = (tuple(obj.pose), obj.elevation, tuple(obj.size), obj.label)
            cached = self.cache.get(i)
            if cached is None or cached[0] != key:
                cached = self.cache[i] = (key, object_markers(seconds, [obj], first_id=i))
            for marker in cached[1]:
                marker.header.stamp = now
            markers += cached[1]
        return markers
