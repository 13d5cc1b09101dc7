"""Labelled activity frames generated with the simulator's camera model (sim2d): a person doing
one activity with its objects, seen from several distances and bearings, with the simulator's
keypoint/depth/colour noise, detector misses and confidences. Used by scripts/eval_activity.

A scene with a partner (chat) is two people facing each other; the robot stands where it sees
both, as a robot watching a conversation would: it views the pair no closer to in line than
where one body starts to hide the other, turns toward the pair and, if that is not enough, steps
back until both torsos and heads are in the image. As in the simulator, a head turned away from
the robot hides its nose and eyes.
"""
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from sim2d.camera import Camera, CameraConfig, hidden_face, project_stacked
from sim2d.detection_model import DetectionConfig
from sim2d.skeleton import (
    L_EAR, L_EYE, L_HIP, L_SHOULDER, NECK, NOSE, R_EAR, R_EYE, R_HIP, R_SHOULDER,
    person_keypoints)
from sim2d.world import SimObject

from perception.localisation import Intrinsics, optical_to_map_transform
from perception.visual_pipeline import FrameView, ObjectBox, PersonView, StackedCameras

SHIRT = ((196, 38, 45), (180, 30, 40), (184, 33, 42))
PARTNER_SHIRT = ((40, 90, 170), (35, 80, 160), (38, 85, 165))
BODY_WIDTH = 0.5        # [m] a standing body with its arms, as the image sees it from any side
TURN_STEPS = 10         # [-] the robot turns toward a pair in this many steps before stepping back
BACK_OFF_STEP = 0.05    # [m] then steps back this far at a time until it sees both people
SEEN_JOINTS = (NOSE, NECK, R_SHOULDER, L_SHOULDER, R_HIP, L_HIP, R_EYE, L_EYE, R_EAR, L_EAR)


@dataclass
class Scene:
    """What the person does: label, posture, held object label, looked-at object (label, where)."""

    label: str
    posture: str
    holding: str = ""                 # COCO label of the held object
    looking: tuple = ()               # (label, forward, left, elevation [m], size (x, y, z))
    extra: tuple = ()                 # more (label, forward, left, elevation, size) in the scene
    partner: float = 0.0              # [m] a standing person this far ahead, facing back (0: none)


SMALL = (0.08, 0.08, 0.12)
SCENES = (
    Scene("eat", "sitting", "fork", ("bowl", 0.45, 0.0, 0.72, (0.15, 0.15, 0.08))),
    Scene("drink", "standing", "cup"),
    # Table 5-3: watching TV from the sofa (the household's couch faces its TV the same way).
    Scene("watch TV", "sitting", "", ("tv", 2.5, 0.0, 0.5, (0.1, 1.0, 0.6)),
          (("couch", -0.15, 0.0, 0.0, (0.8, 2.0, 0.85)),)),
    # Table 5-4: talking with another person, who is a detected person (skeleton and box).
    Scene("chat", "standing", partner=1.2),
    Scene("call", "standing", "cell phone"),
    Scene("read", "sitting", "book"),
    Scene("work", "sitting", "mouse", ("tv", 0.7, 0.0, 0.75, (0.1, 0.55, 0.35))),
    Scene("store", "standing", "bottle", ("refrigerator", 0.7, 0.0, 0.0, (0.6, 0.7, 1.8))),
    Scene("sleep", "lying", "", ("bed", 0.0, 0.0, 0.0, (2.0, 1.4, 0.45))),
    Scene("go out", "standing", "umbrella"),
    Scene("wash", "standing", "toothbrush", ("sink", 0.5, 0.0, 0.8, (0.4, 0.5, 0.15))),
    Scene("others", "standing", "teddy bear"),
    Scene("sitting", "sitting"),
    Scene("standing", "standing"),
    Scene("lying", "lying"),
)


def _object(label, pose_xy, yaw, elevation, size, name):
    return SimObject(name, label, (pose_xy[0], pose_xy[1], yaw), elevation, size)


def _scene_objects(scene, pose, hold):
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    objects = []
    if hold is not None and scene.holding:
        objects.append(_object(scene.holding, hold[:2], yaw, hold[2] - SMALL[2] / 2, SMALL, "held"))
    for i, (label, fwd, left, elev, size) in enumerate(
            ([scene.looking] if scene.looking else []) + list(scene.extra)):
        objects.append(_object(label, (x + c * fwd - s * left, y + s * fwd + c * left), yaw, elev,
                               size, f"o{i}"))
    return objects


def make_camera(config, seed):
    top = CameraConfig(tilt=0.1)
    bottom = CameraConfig(mount_height=1.05, tilt=0.8)
    return Camera(top, bottom, DetectionConfig(**{**config, "seed": seed}), occluders=None)


def stacked_cameras(camera, robot_pose: Sequence[float]) -> StackedCameras:
    """sim2d Camera (top and bottom CameraConfig) at a robot pose -> StackedCameras, as the
    visual node builds them from its camera parameters and tf."""
    parts = {}
    for which, spec in (("top", camera.top), ("bottom", camera.bottom)):
        parts[which] = (Intrinsics(spec.fx, spec.fy, spec.cx, spec.cy, spec.width, spec.height),
                        optical_to_map_transform(robot_pose, spec.mount_x, spec.mount_height,
                                                 spec.tilt))
    return StackedCameras(camera.top.height, {k: v[0] for k, v in parts.items()},
                          {k: v[1] for k, v in parts.items()})


def _pair_poses(distance, bearing, facing, separation):
    """Poses of a person and their partner `separation` [m] apart, facing each other, their
    midpoint `distance` [m] ahead at `bearing` [rad]; `facing` turns the pair's axis from
    side-on (0: both in profile; > 0: the person turns toward the robot), limited to where one
    body does not hide the other (lateral gap >= BODY_WIDTH)."""
    limit = math.acos(min(1.0, BODY_WIDTH / separation))
    axis = bearing + math.pi / 2.0 + max(-limit, min(limit, facing))
    mx, my = distance * math.cos(bearing), distance * math.sin(bearing)
    dx, dy = separation / 2.0 * math.cos(axis), separation / 2.0 * math.sin(axis)
    return (mx - dx, my - dy, axis), (mx + dx, my + dy, axis + math.pi)


def _both_in_view(camera, bodies, robot_pose):
    """True when every SEEN_JOINTS keypoint of every body (less its hidden face) is in the image."""
    for keypoints in bodies:
        _, _, visible, _ = project_stacked(keypoints, robot_pose, camera.top, camera.bottom)
        need = [j for j in SEEN_JOINTS if j not in hidden_face(keypoints, robot_pose)]
        if not visible[need].all():
            return False
    return True


def _viewpoints(distance, bearing, max_range):
    """Where the robot tries to see a pair from, in order: its place, turning the pair's
    midpoint toward the image centre (bearing to 0 in TURN_STEPS), then stepping back."""
    for k in range(TURN_STEPS + 1):
        yield distance, bearing * (1.0 - k / TURN_STEPS)
    while distance + BACK_OFF_STEP <= max_range:
        distance += BACK_OFF_STEP
        yield distance, 0.0


def conversation(scene, camera, distance, bearing, facing, robot_pose):
    """The person's pose and keypoints and the partner's keypoints, from the first viewpoint
    (`_viewpoints`) where the robot sees both (else the last one, at the detectors' max_range)."""
    for distance, bearing in _viewpoints(distance, bearing, camera.detection.max_range):
        pose, partner_pose = _pair_poses(distance, bearing, facing, scene.partner)
        heads = [person_keypoints(posture, p)[0][[R_EAR, L_EAR]].mean(axis=0)
                 for posture, p in ((scene.posture, pose), ("standing", partner_pose))]
        keypoints, _ = person_keypoints(scene.posture, pose, look_target=heads[1])
        partner, _ = person_keypoints("standing", partner_pose, look_target=heads[0])
        if _both_in_view(camera, (keypoints, partner), robot_pose):
            break
    return pose, keypoints, partner


def person_view(skeleton):
    """sim2d SkeletonDetection -> perception PersonView."""
    return PersonView(np.column_stack([skeleton.x, skeleton.y]), skeleton.confidence,
                      skeleton.depth, skeleton.joint_colours)


def object_box(detection):
    """sim2d ObjectDetection -> perception ObjectBox."""
    return ObjectBox(detection.label, detection.confidence, detection.x, detection.y,
                     detection.width, detection.height, detection.depth)


def _add_person(frame, camera, name, keypoints, shirt, robot_pose):
    """Append one person's skeleton and 'person' box unless the detector misses them."""
    if camera.missed():
        return
    skeleton, box = camera.detect_person(name, keypoints, shirt, robot_pose,
                                         hidden=hidden_face(keypoints, robot_pose))
    if skeleton is not None:
        frame.people.append(person_view(skeleton))
        frame.objects.append(object_box(box))


ROBOT_POSE = (0.0, 0.0, 0.0)   # the robot of every scene, at the map origin facing +x


def scene_frame(scene, camera, distance, bearing, facing, robot_pose=ROBOT_POSE):
    """One labelled frame: the person `distance` [m] ahead at `bearing` [rad], body yaw `facing`
    [rad] relative to looking back at the robot (with a partner: see `_pair_poses`). The
    labelled person is the frame's first person."""
    partner = None
    if scene.partner:
        pose, keypoints, partner = conversation(scene, camera, distance, bearing, facing,
                                                robot_pose)
        hold = None
    else:
        px, py = distance * math.cos(bearing), distance * math.sin(bearing)
        pose = (px, py, math.atan2(-py, -px) + facing)
        looked = _scene_objects(scene, pose, None)
        look_target = looked[0].centre() if scene.looking else None
        keypoints, hold = person_keypoints(scene.posture, pose, holding=bool(scene.holding),
                                           look_target=look_target)
    objects = _scene_objects(scene, pose, hold)
    frame = FrameView(*camera.frame_size)
    _add_person(frame, camera, "p", keypoints, SHIRT, robot_pose)
    if partner is not None and frame.people:   # a missed person stays missed
        _add_person(frame, camera, "partner", partner, PARTNER_SHIRT, robot_pose)
    candidates = [(o.name, o.label, o.corners(), o.centre()) for o in objects
                  if not camera.missed()]
    frame.objects += [object_box(det) for det in camera.detect_objects(candidates, robot_pose)]
    return frame


def labelled_frames(distances, bearings, facings, detection, seed=0):
    """[(label, FrameView)] over every scene x distance x bearing x facing, the robot at
    ROBOT_POSE."""
    camera = make_camera(detection, seed)
    return [(scene.label, scene_frame(scene, camera, d, b, f, ROBOT_POSE))
            for scene in SCENES for d in distances for b in bearings for f in facings]
