"""perception's visual pipeline on the simulator's labelled scenes (tamp_bringup.sim_activity_set):
activity, localisation and chat partners read from camera-level frames, and the localisation
transform checked against the simulator's camera."""
import math

import numpy as np
import pytest
from sim2d.camera import CameraConfig, camera_points
from perception.activity import ActivityConfig, load_affordances
from perception.localisation import Intrinsics, optical_to_map_transform, transform_point
from perception.object_memory import ObjectMemory, ObjectMemoryConfig
from perception.visual_pipeline import StackedCameras, analyse_frame

from tamp_resources import resource

from tamp_bringup.sim_activity_set import SCENES, make_camera, scene_frame

TABLE = load_affordances(resource("config") / "affordances.yaml")
NO_NOISE = {"miss_probability": 0.0, "keypoint_noise": 0.0, "depth_noise": 0.0,
            "depth_noise_fraction": 0.0, "colour_noise": 0.0}


def scene(label):
    return next(s for s in SCENES if s.label == label)


def cameras_of(camera, pose=(0.0, 0.0, 0.0)):
    intr = {k: Intrinsics(c.fx, c.fy, c.cx, c.cy, c.width, c.height)
            for k, c in (("top", camera.top), ("bottom", camera.bottom))}
    to_map = {k: optical_to_map_transform(pose, c.mount_x, c.mount_height, c.tilt)
              for k, c in (("top", camera.top), ("bottom", camera.bottom))}
    return StackedCameras(camera.top.height, intr, to_map)


def test_reading_person_is_read_and_localised():
    camera = make_camera(NO_NOISE, seed=1)
    frame = scene_frame(scene("read"), camera, distance=2.0, bearing=0.2, facing=0.6)
    [result] = analyse_frame(frame, TABLE, ActivityConfig(), cameras_of(camera))
    assert result.activity.activity == "read"
    assert result.activity.near_hands == ["book"]
    truth = (2.0 * math.cos(0.2), 2.0 * math.sin(0.2))
    # the neck's depth is the body's front, within a few cm of the feet position
    assert math.dist(result.position, truth) < 0.15
    assert result.shirt.shape == (3, 3) and result.shirt[0].tolist() == [196, 38, 45]


def test_missing_torso_depth_is_a_problem_not_an_exception():
    camera = make_camera(NO_NOISE, seed=1)
    frame = scene_frame(scene("standing"), camera, distance=2.0, bearing=0.0, facing=0.0)
    frame.people[0].depth[:] = np.nan
    [result] = analyse_frame(frame, TABLE, ActivityConfig(), cameras_of(camera))
    assert result.position is None
    assert any("depth" in p for p in result.problems)
    assert result.activity.activity == "standing"


def test_own_person_box_is_not_a_chat_partner():
    camera = make_camera(NO_NOISE, seed=1)
    frame = scene_frame(scene("standing"), camera, distance=2.0, bearing=0.0, facing=1.2)
    [result] = analyse_frame(frame, TABLE, ActivityConfig())
    assert "person" not in result.activity.in_eyesight + result.activity.near_hands


def test_conversation_turned_toward_the_robot_is_chat():
    """The chat scene turned 0.8 rad from side-on: the person faces the robot (no box in their
    eyesight, Fig. 3-12 (a)); the partner's skeleton, 1.2 m away and facing them, is the person
    in O_e, counted once. Each person is the other's partner."""
    camera = make_camera(NO_NOISE, seed=1)
    frame = scene_frame(scene("chat"), camera, distance=2.5, bearing=0.0, facing=0.8)
    assert len(frame.people) == 2
    first, second = analyse_frame(frame, TABLE, ActivityConfig())
    assert first.activity.in_eyesight == ["person"]
    assert first.activity.activity == "chat" and second.activity.activity == "chat"
    [alone] = analyse_frame(frame, TABLE, ActivityConfig(partners_from_skeletons=False))[:1]
    assert alone.activity.activity == "standing"


@pytest.fixture


def test_transform_inverts_the_simulator_camera():
    """optical_to_map_transform is the inverse of sim2d.camera.camera_points for any pose/tilt."""
    cam = CameraConfig(mount_x=0.09, mount_height=1.15, tilt=0.1)
    pose = (5.4, 5.0, 3.14159)
    points = np.array([[3.0, 4.5, 1.2], [4.0, 6.0, 0.3], [2.0, 5.0, 1.7]])
    optical = camera_points(points, pose, cam)
    T = optical_to_map_transform(pose, cam.mount_x, cam.mount_height, cam.tilt)
    for p_opt, p_map in zip(optical, points):
        assert transform_point(T, p_opt) == pytest.approx(p_map, abs=1e-9)


def test_an_umbrella_the_next_frame_misses_is_remembered_within_reach():
    """The umbrella by the door, detected in three frames, is still at the person's hand when the
    detector misses it: with the object memory the person still reads as going out; without,
    standing."""
    camera = make_camera(NO_NOISE, seed=1)
    frame = scene_frame(scene("go out"), camera, distance=2.0, bearing=0.0, facing=0.6)
    cameras = cameras_of(camera)
    memory = ObjectMemory(ObjectMemoryConfig(confirm=3))
    for stamp in (0.0, 0.1, 0.2):
        [seen] = analyse_frame(frame, TABLE, ActivityConfig(), cameras, memory=memory,
                               stamp=stamp)
        assert seen.activity.activity == "go out" and seen.activity.near_hands == ["umbrella"]
    frame.objects = [o for o in frame.objects if o.label != "umbrella"]
    [missed] = analyse_frame(frame, TABLE, ActivityConfig(), cameras, memory=memory, stamp=1.0)
    assert missed.activity.activity == "go out" and missed.activity.near_hands == ["umbrella"]
    [alone] = analyse_frame(frame, TABLE, ActivityConfig(), cameras)
    assert alone.activity.activity == "standing"
