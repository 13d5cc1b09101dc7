"""Frame -> per-person results on simulator frames; self-generated instructions (Sec. 4.2.1)."""
import math
import os

import numpy as np
import pytest
from human_db.model import ScheduleEntry
from human_db.schedule import check_schedule
from floorplan.semantic_graph import load_graph
from task_planner.instruction import ROBOT
from task_planner.reward import load_priorities

from perception.activity import load_affordances
from perception.requests import load_keyword_config
from perception.self_instructions import (
    Observation, SelfInstructionConfig, SelfInstructionGenerator)
from perception.keypoints import L_ANKLE, NECK, NUM_KEYPOINTS, R_HIP
from perception.localisation import (Intrinsics, optical_to_map_transform, pixel_to_camera,
                                     stitched_pixel, transform_point)
from perception.visual_pipeline import (ObjectBox, PersonView, StackedCameras, joints_in_map,
                                        stitched_points_to_map, stitched_to_map,
                                        object_extent, unknown_classes)
from tamp_resources import resource

CONFIG = resource("config")
TABLE = load_affordances(os.path.join(CONFIG, "affordances.yaml"))
NO_NOISE = {"miss_probability": 0.0, "keypoint_noise": 0.0, "depth_noise": 0.0,
            "depth_noise_fraction": 0.0, "colour_noise": 0.0}


@pytest.fixture
def generator():
    keywords = load_keyword_config(os.path.join(CONFIG, "keywords.yaml"))
    functions = {name: (f.code, f.duration_s) for name, f in keywords.functions.items()}
    priority = load_priorities(os.path.join(CONFIG, "priorities.yaml"))["self_generated"]
    graph = load_graph(os.path.join(CONFIG, "..", "maps", "household.graph.yaml"))
    config = SelfInstructionConfig(recommendations={"read": "play_music"}, repeat_after=600.0)
    codes = {a: i + 1 for i, a in enumerate(TABLE.activities)}
    generator = SelfInstructionGenerator(config, functions, priority, graph.place_ids(), codes)
    return generator, functions


def test_reading_person_gets_piano_music(generator):
    gen, functions = generator
    [made] = gen.generate(Observation("Alice", "read", "living_room", 100.0))
    assert made.type == ROBOT and made.function == functions["play_music"][0]
    assert (made.gamma, made.beta) == (1.0, 0.9)          # config/priorities.yaml self-generated
    assert made.target == "Alice" and made.destination_name == "living_room"
    assert gen.generate(Observation("Alice", "read", "living_room", 200.0)) == []   # repeat_after
    assert len(gen.generate(Observation("Alice", "read", "living_room", 701.0))) == 1


def test_schedule_deviation_gives_a_reminder(generator):
    gen, functions = generator

    class Person:
        location, activity = "", ""
        schedules = (ScheduleEntry(start=20 * 3600.0, end=21 * 3600.0, place="living_room",
                                   activity="watch TV"),)
    check = check_schedule(Person(), 20.5 * 3600, location="office", activity="work")
    made = gen.generate(Observation("Bob", "work", "office", 10.0), check)
    assert [m.function for m in made] == [functions["remind"][0]]
    assert "watch TV" in made[0].text and made[0].destination_name == "office"


def test_only_really_unknown_classes_are_named():
    """Issue 32: "unknown object classes ignored: ['chair', 'dining table']" every 10 s."""
    objects = [ObjectBox(label, 0.9, 0, 0, 10, 10) for label in
               ("chair", "dining table", "couch", "person", "zeppelin", "zeppelin", "airship")]
    assert unknown_classes(objects, TABLE) == ["airship", "zeppelin"]


def test_deviation_may_check_on_the_person_instead(generator):
    _, functions = generator
    priority = load_priorities(os.path.join(CONFIG, "priorities.yaml"))["self_generated"]
    graph = load_graph(os.path.join(CONFIG, "..", "maps", "household.graph.yaml"))
    gen = SelfInstructionGenerator(SelfInstructionConfig(deviation_function="check_status"),
                                   functions, priority, graph.place_ids(), {})
    entry = ScheduleEntry(start=18.5 * 3600, end=19 * 3600, place="dining_room", activity="eat")

    class David:
        location, activity, schedules = "", "", (entry,)
    check = check_schedule(David(), 18.6 * 3600, location="bedroom", activity="read")
    [made] = gen.generate(Observation("David", "read", "bedroom", 10.0), check)
    assert made.function == functions["check_status"][0] and made.target == "David"
    assert made.text == ("check status David: schedule says 'eat' in dining_room, observed "
                         "'read' in bedroom")


def test_reminder_when_a_schedule_entry_starts(generator):
    gen, functions = generator
    eat = ScheduleEntry(start=18.5 * 3600, end=19 * 3600, place="dining_room", activity="eat")
    sleep = ScheduleEntry(start=23 * 3600, end=6 * 3600, place="bedroom", activity="sleep")

    class Bob:
        name, location, schedules = "Bob", "living_room", (eat, sleep)
    assert gen.due_reminders([Bob()], 18.4 * 3600, 18.49 * 3600, 5.0) == []
    [made] = gen.due_reminders([Bob()], 18.49 * 3600, 18.5 * 3600, 6.0)
    assert made.function == functions["remind"][0] and made.target == "Bob"
    assert made.destination_name == "living_room"      # where he was last seen
    assert made.text == "remind Bob: time to eat in the dining_room"
    # across midnight: 23:00 lies in (22:59:59, 00:00:01]
    [late] = gen.due_reminders([Bob()], 23 * 3600 - 1, 1.0, 700.0)
    assert late.text == "remind Bob: time to sleep in the bedroom"


def test_joints_come_back_to_where_they_are_in_the_map():
    """Neck and hips projected into the top camera, an ankle into the bottom one (the stitched
    frame's lower half), through Eqs. 3-3..3-5 and the cameras' poses, and back: the joints in
    the map; a joint without depth or confidence stays unknown."""
    intr = Intrinsics(583.9, 588.5, 320.0, 240.0, 640, 480)
    robot = (1.0, 2.0, math.pi / 2)
    to_map = {"top": optical_to_map_transform(robot, 0.09, 1.15, 0.1),
              "bottom": optical_to_map_transform(robot, 0.09, 1.05, 0.8)}
    cameras = StackedCameras(480, {"top": intr, "bottom": intr}, to_map)
    where = {NECK: ("top", (1.0, 4.0, 1.03)), R_HIP: ("top", (0.9, 4.0, 0.48)),
             L_ANKLE: ("bottom", (1.1, 3.2, 0.08))}
    points, depth = np.zeros((NUM_KEYPOINTS, 2)), np.full(NUM_KEYPOINTS, np.nan)
    confidence = np.zeros(NUM_KEYPOINTS)
    for joint, (which, xyz) in where.items():
        x, y, z = (np.linalg.inv(to_map[which]) @ np.append(xyz, 1.0))[:3]
        points[joint] = (intr.fx * x / z + intr.cx,
                         intr.fy * y / z + intr.cy + (480 if which == "bottom" else 0))
        depth[joint], confidence[joint] = z, 0.9
    body = joints_in_map(PersonView(points, confidence, depth, np.zeros((3, 3))), cameras, 0.3)
    for joint, (_, xyz) in where.items():
        assert body[joint] == pytest.approx(xyz, abs=1e-9)
    assert np.isnan(np.delete(body, list(where), axis=0)).all()
    depth[NECK] = 0.1                                          # below the valid depth
    body = joints_in_map(PersonView(points, confidence, depth, np.zeros((3, 3))), cameras, 0.3)
    assert np.isnan(body[NECK]).all()


def test_an_objects_box_in_the_map_spans_its_image_box_at_its_depth():
    """A 100 x 50 px box centred on the top camera's axis at 2 m, the robot at the origin facing
    +x, the camera level: its front 100 / 583.9 x 2 = 0.34 m across (y) and 50 / 588.5 x 2 =
    0.17 m high (z) at x = 2.09 m; it is as deep as its smaller side, t = 0.17 m, so its back,
    at 2 + t from the camera, spans the image box at that depth. No box without a depth."""
    intr = Intrinsics(583.9, 588.5, 320.0, 240.0, 640, 480)
    to_map = {"top": optical_to_map_transform((0.0, 0.0, 0.0), 0.09, 1.15, 0.0),
              "bottom": optical_to_map_transform((0.0, 0.0, 0.0), 0.09, 1.05, 0.8)}
    cameras = StackedCameras(480, {"top": intr, "bottom": intr}, to_map)
    box = ObjectBox("laptop", 0.9, 270.0, 215.0, 100.0, 50.0, 2.0)
    low, high = object_extent(box, cameras, 0.3)
    t = 50 / 588.5 * 2.0
    back = 2.0 + t
    assert low == pytest.approx([2.09, -50 / 583.9 * back, 1.15 - 25 / 588.5 * back], abs=1e-6)
    assert high == pytest.approx([2.09 + t, 50 / 583.9 * back, 1.15 + 25 / 588.5 * back],
                                 abs=1e-6)
    assert object_extent(ObjectBox("cup", 0.9, 0, 0, 10, 10, float("nan")), cameras, 0.3) is None


def test_many_stitched_pixels_go_to_the_map_as_one_at_a_time():
    """stitched_points_to_map (one matrix product per camera) gives, for pixels of the top
    camera, of the bottom one and on the seam, the point of Eqs. 3-3..3-5 in the camera that saw
    it (stitched_pixel, pixel_to_camera) moved by that camera's pose (transform_point)."""
    intr = Intrinsics(583.9, 588.5, 320.0, 240.0, 640, 480)
    robot = (1.0, 2.0, 0.7)
    to_map = {"top": optical_to_map_transform(robot, 0.09, 1.15, 0.1),
              "bottom": optical_to_map_transform(robot, 0.09, 1.05, 0.8)}
    cameras = StackedCameras(480, {"top": intr, "bottom": intr}, to_map)
    u = np.array([10.0, 320.0, 600.0, 100.0, 479.0])
    v = np.array([5.0, 479.9, 480.0, 900.0, 240.0])
    depth = np.array([0.5, 2.0, 1.2, 3.5, 7.0])
    many = stitched_points_to_map(u, v, depth, cameras)
    for point, pixel in zip(many, zip(u, v, depth)):
        which, u_cam, v_cam = stitched_pixel(pixel[0], pixel[1], 480)
        one = transform_point(to_map[which], pixel_to_camera(u_cam, v_cam, pixel[2], intr))
        assert point == pytest.approx(one, abs=1e-12)
        assert stitched_to_map(*pixel, cameras) == pytest.approx(one, abs=1e-12)
    assert [p[0] for p in zip(u, v) if stitched_pixel(*p, 480)[0] == "bottom"] == [600.0, 100.0]
