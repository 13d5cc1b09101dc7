"""Labelled activity frames generated with the simulator's camera model (sim2d): a person doing
one activity with its objects, seen from several distances and bearings, with the simulator's
keypoint/depth/colour noise, detector misses and confidences. Used by scripts/eval_activity.
"""
import math
from dataclasses import dataclass

import numpy as np
from sim2d.camera import Camera, CameraConfig, DetectionConfig
from sim2d.skeleton import person_keypoints
from sim2d.world import SimObject

from perception.visual_pipeline import FrameView, ObjectBox, PersonView

SHIRT = ((196, 38, 45), (180, 30, 40), (184, 33, 42))


@dataclass
class Scene:
    """What the person does: label, posture, held object label, looked-at object (label, where)."""

    label: str
    posture: str
    holding: str = ""                 # COCO label of the held object
    looking: tuple = ()               # (label, forward, left, elevation [m], size (x, y, z))
    extra: tuple = ()                 # more (label, forward, left, elevation, size) in the scene


SMALL = (0.08, 0.08, 0.12)
SCENES = (
    Scene("eat", "sitting", "fork", ("bowl", 0.45, 0.0, 0.72, (0.15, 0.15, 0.08))),
    Scene("drink", "standing", "cup"),
    # Table 5-3: watching TV from the sofa (the household's couch faces its TV the same way).
    Scene("watch TV", "sitting", "", ("tv", 2.5, 0.0, 0.5, (0.1, 1.0, 0.6)),
          (("couch", -0.15, 0.0, 0.0, (0.8, 2.0, 0.85)),)),
    Scene("chat", "standing", "", ("person", 1.2, 0.0, 0.0, (0.4, 0.5, 1.7))),
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


def scene_frame(scene, camera, distance, bearing, facing, robot_pose=(0.0, 0.0, 0.0)):
    """One labelled frame: the person `distance` [m] ahead at `bearing` [rad], body yaw `facing`
    [rad] relative to looking back at the robot."""
    px, py = distance * math.cos(bearing), distance * math.sin(bearing)
    yaw = math.atan2(-py, -px) + facing
    pose = (px, py, yaw)
    looked = _scene_objects(scene, pose, None)
    look_target = looked[0].centre() if scene.looking else None
    keypoints, hold = person_keypoints(scene.posture, pose, holding=bool(scene.holding),
                                       look_target=look_target)
    objects = _scene_objects(scene, pose, hold)
    frame = FrameView(*camera.frame_size)
    if not camera.missed():
        skeleton, box = camera.detect_person("p", keypoints, SHIRT, robot_pose)
        if skeleton is not None:
            frame.people.append(PersonView(np.column_stack([skeleton.x, skeleton.y]),
                                           skeleton.confidence, skeleton.depth,
                                           skeleton.joint_colours))
            frame.objects.append(ObjectBox("person", box.confidence, box.x, box.y, box.width,
                                           box.height, box.depth))
    candidates = [(o.name, o.label, o.corners(), o.centre()) for o in objects
                  if not camera.missed()]
    for det in camera.detect_objects(candidates, robot_pose):
        frame.objects.append(ObjectBox(det.label, det.confidence, det.x, det.y, det.width,
                                       det.height, det.depth))
    return frame


def labelled_frames(distances, bearings, facings, detection, seed=0):
    """[(label, FrameView)] over every scene x distance x bearing x facing."""
    camera = make_camera(detection, seed)
    return [(scene.label, scene_frame(scene, camera, d, b, f))
            for scene in SCENES for d in distances for b in bearings for f in facings]
