"""3D COCO-18 body keypoints (OpenPose order, thesis 000 Fig. 3-4) for a posture and activity.

Person frame: x forward, y left, z up [m]; the feet stand at the origin. Arms hang for an idle
person; a person holding something has both wrists at the held point in front of the chest (on
the top of a table or desk in front of a seated person: hands rest on it, not under it); the head
(nose, eyes, ears) turns toward what the person looks at (the held object by default).
"""
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

NOSE, NECK, R_SHOULDER, R_ELBOW, R_WRIST, L_SHOULDER, L_ELBOW, L_WRIST = range(8)
R_HIP, R_KNEE, R_ANKLE, L_HIP, L_KNEE, L_ANKLE, R_EYE, L_EYE, R_EAR, L_EAR = range(8, 18)
HEAD = (NOSE, R_EYE, L_EYE, R_EAR, L_EAR)
NUM_KEYPOINTS = 18
Points = npt.NDArray[np.float64]   # (n, 3) [m]

STANDING = np.array([
    [0.09, 0.0, 1.60], [0.0, 0.0, 1.45], [0.0, -0.19, 1.42], [0.0, -0.23, 1.14],
    [0.02, -0.24, 0.88], [0.0, 0.19, 1.42], [0.0, 0.23, 1.14], [0.02, 0.24, 0.88],
    [0.0, -0.10, 0.95], [0.02, -0.10, 0.52], [0.0, -0.10, 0.08], [0.0, 0.10, 0.95],
    [0.02, 0.10, 0.52], [0.0, 0.10, 0.08], [0.08, -0.035, 1.64], [0.08, 0.035, 1.64],
    [0.0, -0.075, 1.62], [0.0, 0.075, 1.62]])

SITTING = np.array([
    [0.09, 0.0, 1.18], [0.0, 0.0, 1.03], [0.0, -0.19, 1.00], [0.05, -0.23, 0.74],
    [0.25, -0.20, 0.62], [0.0, 0.19, 1.00], [0.05, 0.23, 0.74], [0.25, 0.20, 0.62],
    [0.0, -0.10, 0.48], [0.45, -0.10, 0.50], [0.45, -0.10, 0.08], [0.0, 0.10, 0.48],
    [0.45, 0.10, 0.50], [0.45, 0.10, 0.08], [0.08, -0.035, 1.22], [0.08, 0.035, 1.22],
    [0.0, -0.075, 1.20], [0.0, 0.075, 1.20]])

LYING_HEIGHT = 0.5      # [m] height of the back of a lying person (bed, sofa)
HEAD_PIVOT = 0.12       # [m] head rotation centre above the neck
HOLD_REACH = 0.32       # [m] held point in front of the chest
HOLD_DROP = 0.35        # [m] held point below the shoulders
HAND_SPREAD = 0.08      # [m] half distance between the hands holding something
HAND_ABOVE_SURFACE = 0.06  # [m] held point above the top of the furniture under the hands
MAX_HEAD_YAW = 1.3      # [rad]
MAX_HEAD_PITCH = 0.9    # [rad]


def posture_keypoints(posture: str) -> Points:
    """Idle keypoints (18, 3) in the person frame for standing, sitting or lying."""
    if posture == "standing":
        return STANDING.copy()
    if posture == "sitting":
        return SITTING.copy()
    if posture == "lying":   # the standing body tipped backwards: head towards +x, face up
        body = STANDING.copy()
        return np.column_stack([body[:, 2] - 0.85, body[:, 1], LYING_HEIGHT + body[:, 0]])
    raise ValueError(f"unknown posture {posture!r} (standing, sitting, lying)")


def hold_point(points: Points) -> Points:
    """Person-frame point [m] where the hands hold an object (in front of the chest)."""
    shoulders = (points[R_SHOULDER] + points[L_SHOULDER]) / 2.0
    return shoulders + np.array([HOLD_REACH, 0.0, -HOLD_DROP])


def hold_in_hands(points: Points, surface: float | None = None) -> Points:
    """Move both arms so the wrists meet at the hold point; returns the hold point. `surface`:
    the top [m] of the furniture under the hands (a table at which the person sits): the hold
    point is raised onto it."""
    target = hold_point(points)
    if surface is not None:
        target[2] = max(target[2], surface + HAND_ABOVE_SURFACE)
    for shoulder, elbow, wrist, side in ((R_SHOULDER, R_ELBOW, R_WRIST, -1.0),
                                         (L_SHOULDER, L_ELBOW, L_WRIST, 1.0)):
        hand = target + np.array([0.0, side * HAND_SPREAD, 0.0])
        points[wrist] = hand
        points[elbow] = (points[shoulder] + hand) / 2.0 + np.array([-0.08, side * 0.06, -0.08])
    return target


def turn_head(points: Points, target: npt.ArrayLike) -> None:
    """Rotate the head keypoints about the head centre to face the person-frame point target."""
    pivot = points[NECK] + np.array([0.0, 0.0, HEAD_PIVOT])
    d = np.asarray(target, dtype=float) - pivot
    yaw = max(-MAX_HEAD_YAW, min(MAX_HEAD_YAW, math.atan2(d[1], d[0])))
    pitch = max(-MAX_HEAD_PITCH, min(MAX_HEAD_PITCH, math.atan2(-d[2], math.hypot(d[0], d[1]))))
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])   # +pitch looks down
    for k in HEAD:
        points[k] = pivot + rz @ (ry @ (points[k] - pivot))


def to_world(points: Points, pose: Sequence[float]) -> Points:
    """Person-frame points -> map frame, given the person's pose (x, y, yaw)."""
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    out = points.copy()
    out[:, 0] = x + c * points[:, 0] - s * points[:, 1]
    out[:, 1] = y + s * points[:, 0] + c * points[:, 1]
    return out


def to_person(point: Sequence[float] | np.ndarray, pose: Sequence[float]) -> Points:
    """Map-frame point -> person frame."""
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    dx, dy = point[0] - x, point[1] - y
    return np.array([c * dx + s * dy, -s * dx + c * dy, point[2]])


def person_keypoints(posture: str, pose: Sequence[float], holding: bool = False,
                     look_target: Sequence[float] | np.ndarray | None = None,
                     surface: float | None = None) -> tuple[Points, Points | None]:
    """Map-frame keypoints (18, 3) and the map-frame hold point (None if not holding);
    `surface`: the top [m] of the furniture under the held point (hold_in_hands)."""
    points = posture_keypoints(posture)
    hold = hold_in_hands(points, surface) if holding and posture != "lying" else None
    if look_target is not None:
        turn_head(points, to_person(look_target, pose))
    elif hold is not None:
        turn_head(points, hold)
    world = to_world(points, pose)
    hold_world = None if hold is None else to_world(hold[None, :], pose)[0]
    return world, hold_world
