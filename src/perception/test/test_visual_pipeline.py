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

from perception.activity import ActivityConfig, load_affordances
from perception.localisation import optical_to_map_transform, Intrinsics
from perception.requests import load_keyword_config
from perception.self_instructions import (
    Observation, SelfInstructionConfig, SelfInstructionGenerator)
from perception.sim_activity_set import SCENES, make_camera, scene_frame
from perception.visual_pipeline import ObjectBox, StackedCameras, analyse_frame, unknown_classes

CONFIG = os.path.join(os.path.dirname(__file__), "..", "..", "..", "config")
TABLE = load_affordances(os.path.join(CONFIG, "affordances.yaml"))
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
