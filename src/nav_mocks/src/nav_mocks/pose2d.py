"""Planar rigid transforms (x, y, yaw): composition, inverse, angle wrapping. ROS-free."""
import math

from sim2d.kinematics import wrap_angle  # the workspace's one definition; re-exported here


def compose(a, b):
    """a ⊕ b: pose b (expressed in frame a) in a's parent frame."""
    ax, ay, ath = a
    bx, by, bth = b
    c, s = math.cos(ath), math.sin(ath)
    return (ax + c * bx - s * by, ay + s * bx + c * by, wrap_angle(ath + bth))


def inverse(a):
    """⊖a: the transform that undoes a."""
    ax, ay, ath = a
    c, s = math.cos(ath), math.sin(ath)
    return (-c * ax - s * ay, s * ax - c * ay, wrap_angle(-ath))


def between(a, b):
    """⊖a ⊕ b: pose b seen from pose a."""
    return compose(inverse(a), b)


def distance(a, b):
    """Euclidean distance [m] between the positions of two poses."""
    return math.hypot(a[0] - b[0], a[1] - b[1])
