"""World files, commands, odometry, people and the camera model, against hand calculations."""
import copy
import math

import numpy as np
import pytest
import yaml
from sim2d_fixtures import LASER_DIR, REPO

from sim2d.camera import CameraConfig, camera_points, project
from floorplan.occupancy_map import MapError
from sim2d.laser import box_ranges
from sim2d.world import CommandError, World
from sim2d.world_config import WorldError, load_world_config

CAMERA = {"rate": 5.0,
          "top": {"mount_x": 0.09, "mount_height": 1.15, "tilt": 0.0},
          "bottom": {"mount_x": 0.09, "mount_height": 1.05, "tilt": 0.8},
          "detection": {"miss_probability": 0.0, "keypoint_noise": 1.0, "seed": 4}}


def world_dict(map_path):
    return {
        "map": str(map_path),
        "robots": [{"name": "pepper", "drive": "holonomic", "radius": 0.3,
                    "pose": [2.0, 3.0, 0.0],
                    "lasers": [{"model": "pepper", "mount": [0.0, 0.0, 0.0]}],
                    "camera": copy.deepcopy(CAMERA)},
                   {"name": "penguin", "drive": "differential", "radius": 0.3,
                    "pose": [2.0, 8.5, 0.0], "namespace": "penguin",
                    "odometry": {"alpha_rot_rot": 0.0, "alpha_rot_trans": 0.0,
                                 "alpha_trans_trans": 0.0, "alpha_trans_rot": 0.0},
                    "lasers": [{"model": "utm_30lx"}]}],
        "people": [{"name": "Bob", "shirt_colour": [35, 70, 190], "pose": [4.0, 3.0, math.pi],
                    "posture": "standing", "activity": "read", "holding": "book",
                    "schedule": [{"time": 1.0, "pose": [3.0, 5.0, 0.0], "posture": "sitting",
                                  "activity": "eat", "via": [[4.0, 5.0]]}]}],
        "objects": [
            {"name": "cup", "label": "cup", "pose": [4.0, 2.4, 0.0], "elevation": 0.8,
             "size": [0.08, 0.08, 0.1]},
            {"name": "book", "label": "book", "pose": [4.0, 3.0, 0.0], "elevation": 0.8,
             "size": [0.2, 0.15, 0.03]},
            {"name": "tv", "label": "tv", "pose": [7.0, 3.0, math.pi], "elevation": 0.6,
             "size": [0.1, 1.0, 0.6]},
            {"name": "chair", "label": "chair", "pose": [0.6, 3.0, 0.0], "elevation": 0.0,
             "size": [0.5, 0.5, 0.9]}]}


def write_world(tmp_path, data):
    path = tmp_path / "world.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.fixture
def world(tmp_path, room_map):
    return World(load_world_config(write_world(tmp_path, world_dict(room_map)), LASER_DIR),
                 cache_dir=None)


def test_pinhole_projection_matches_hand_calculation():
    camera = CameraConfig(fx=583.9, fy=588.5, cx=320.0, cy=240.0, mount_x=0.09,
                          mount_height=1.15, tilt=0.0)
    point = np.array([[2.0 + 0.09 + 2.0, 3.0 + 0.5, 1.15]])   # 2 m ahead, 0.5 m to the left
    u, v, inside = project(camera_points(point, (2.0, 3.0, 0.0), camera), camera)
    assert u[0] == pytest.approx(320.0 - 583.9 * 0.5 / 2.0)
    assert v[0] == pytest.approx(240.0)
    assert inside[0]


def test_person_keypoints_fall_inside_the_person_box(world):
    frame = world.camera_frame("pepper")
    assert len(frame.skeletons) == 1
    skeleton = frame.skeletons[0]
    box = next(o for o in frame.objects if o.label == "person")
    seen = skeleton.confidence > 0
    assert seen.sum() >= 14
    assert np.all(skeleton.x[seen] >= box.x) and np.all(skeleton.x[seen] <= box.x + box.width)
    assert np.all(skeleton.y[seen] >= box.y) and np.all(skeleton.y[seen] <= box.y + box.height)
    assert box.depth == pytest.approx(2.0 - 0.09, abs=0.3)
    # shirt colour read at joints 1, 2 and 5, close to Bob's shirt
    assert np.abs(skeleton.joint_colours.astype(int) - [35, 70, 190]).max() < 30


def test_hands_are_near_the_held_book(world):
    frame = world.camera_frame("pepper")
    skeleton = frame.skeletons[0]
    book = next(o for o in frame.objects if o.label == "book")
    centre = (book.x + book.width / 2.0, book.y + book.height / 2.0)
    for wrist in (4, 7):
        assert math.hypot(skeleton.x[wrist] - centre[0], skeleton.y[wrist] - centre[1]) < 60


def test_objects_behind_a_wall_or_the_camera_are_not_detected(world):
    labels = {o.label for o in world.camera_frame("pepper").objects}
    assert "cup" in labels
    assert "tv" not in labels        # behind the wall at x = 5 m
    assert "chair" not in labels     # behind the robot: outside the field of view


def test_person_walks_her_schedule(tmp_path, room_map):
    data = world_dict(room_map)
    data["robots"] = data["robots"][:1]    # no Penguin: its 1081-beam scans are not checked here
    world = World(load_world_config(write_world(tmp_path, data), LASER_DIR), cache_dir=None)
    for _ in range(int(10.0 / 0.05)):
        world.step(0.05)
    bob = world.people[0]
    assert bob.pose == pytest.approx((3.0, 5.0, 0.0))
    assert (bob.posture, bob.activity) == ("sitting", "eat")


def test_scan_rate_follows_the_laser_model(world):
    for _ in range(40):
        world.step(0.025)                       # 1 s
    assert world.robot("penguin").scans[0].count == 40   # UTM-30LX: 25 ms per scan
    assert world.robot("pepper").scans[0].count == 10    # Pepper: 100 ms per scan
    assert world.robot("penguin").scans[0].ranges.shape == (1081,)


def test_noise_free_odometry_equals_the_motion(world):
    world.set_wheel_speeds("penguin", 2.0, 3.0)
    for _ in range(100):
        world.step(0.02)
    robot = world.robot("penguin")
    x, y, yaw = robot.state.pose
    ox, oy, oyaw = robot.odometry.pose            # odom frame = start pose (2.0, 8.5, 0)
    assert (ox + 2.0, oy + 8.5, oyaw) == pytest.approx((x, y, yaw), abs=1e-9)


def test_nan_command_is_refused(world):
    with pytest.raises(CommandError, match="non-finite"):
        world.set_twist("pepper", float("nan"), 0.0, 0.0)
    with pytest.raises(CommandError, match="non-finite"):
        world.set_wheel_speeds("penguin", 1.0, float("inf"))
    with pytest.raises(CommandError, match="differential"):
        world.set_twist("penguin", 0.1, 0.2, 0.0)


def test_a_world_on_a_base_takes_its_keys_and_replaces_those_it_gives(tmp_path, room_map):
    base_dir = tmp_path / "base"
    base_dir.mkdir()
    base = dict(world_dict(room_map), map="../room.yaml")   # relative to the base's folder
    (base_dir / "day.yaml").write_text(yaml.safe_dump(base))
    one_robot = dict(base="base/day.yaml", robots=world_dict(room_map)["robots"][1:])
    config = load_world_config(write_world(tmp_path, one_robot), LASER_DIR)
    assert [r.name for r in config.robots] == ["penguin"]
    assert [p.name for p in config.people] == ["Bob"] and len(config.objects) == 4
    assert config.map_path == room_map.resolve()
    (base_dir / "day.yaml").write_text(yaml.safe_dump(dict(base, base="other.yaml")))
    with pytest.raises(WorldError, match="names a base of its own"):
        load_world_config(write_world(tmp_path, one_robot), LASER_DIR)


def test_unknown_laser_model_is_a_clear_error(tmp_path, room_map):
    data = world_dict(room_map)
    data["robots"][0]["lasers"][0]["model"] = "lms_100"
    with pytest.raises(WorldError, match=r"unknown laser model 'lms_100' .*utm_30lx"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


def test_missing_map_image_is_a_clear_error(tmp_path, room_map):
    (room_map.parent / "room.pgm").unlink()
    with pytest.raises(MapError, match="map image missing"):
        World(load_world_config(write_world(tmp_path, world_dict(room_map)), LASER_DIR))


def test_robot_inside_a_wall_is_a_clear_error(tmp_path, room_map):
    data = world_dict(room_map)
    data["robots"][0]["pose"] = [5.1, 3.0, 0.0]
    with pytest.raises(WorldError, match="robot 'pepper' at .* inside or touching an obstacle"):
        World(load_world_config(write_world(tmp_path, data), LASER_DIR))


def test_unknown_object_reference_is_a_clear_error(tmp_path, room_map):
    data = world_dict(room_map)
    data["people"][0]["holding"] = "sandwich"
    with pytest.raises(WorldError, match="unknown object 'sandwich'"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


def test_face_is_not_seen_from_behind(tmp_path, room_map):
    data = world_dict(room_map)
    data["people"][0]["pose"] = [4.0, 3.0, 0.0]          # Bob turns his back to the robot
    data["people"][0]["holding"] = ""
    world = World(load_world_config(write_world(tmp_path, data), LASER_DIR))
    skeleton = world.camera_frame("pepper").skeletons[0]
    assert np.all(skeleton.confidence[[0, 14, 15]] == 0)     # nose, eyes
    assert np.all(skeleton.confidence[[1, 2, 5]] > 0)        # neck, shoulders


def test_sitting_person_is_lower_in_the_image_than_standing(world):
    standing = world.camera_frame("pepper").skeletons[0]
    world.people[0].posture = "sitting"
    sitting = world.camera_frame("pepper").skeletons[0]
    assert sitting.y[0] > standing.y[0] + 50           # nose lower (larger row) when sitting


def test_place_robot_starts_an_episode_at_rest(world):
    world.set_wheel_speeds("penguin", 4.0, 4.0)
    for _ in range(20):
        world.step(0.025)
    world.place_robot("penguin", (2.0, 9.0, math.pi / 2))
    robot = world.robot("penguin")
    assert robot.state.pose == (2.0, 9.0, math.pi / 2)
    assert robot.state.twist == (0.0, 0.0, 0.0) and robot.odometry.pose == (0.0, 0.0, 0.0)
    world.step(0.025)
    assert robot.scans[0].count == 1
    with pytest.raises(WorldError, match="cannot be placed"):
        world.place_robot("penguin", (5.1, 3.0, 0.0))


def test_household_people_agree_with_the_human_database():
    """config/worlds/household.yaml dresses the people of config/household.yaml in the shirts
    of config/household_shirts.yaml (the human database has none until the robot meets them)."""
    repo = REPO
    humans = yaml.safe_load((repo / "config" / "household.yaml").read_text())["humans"]
    shirts = yaml.safe_load((repo / "config" / "household_shirts.yaml").read_text())["shirts"]
    assert sorted(shirts) == sorted(h["name"] for h in humans)
    expected = {name: tuple(tuple(shirt[k]) for k in ("joint1", "joint2", "joint5"))
                for name, shirt in shirts.items()}
    world = load_world_config(repo / "config" / "worlds" / "household.yaml", LASER_DIR)
    assert {p.name: p.shirt_colour for p in world.people} == expected
    assert len(world.objects) >= 30


DOOR = {"name": "east", "box": [5.0, 8.0, 5.2, 9.9]}   # closes the room's wall gap (y 8-10 m)


@pytest.fixture
def door_world(tmp_path, room_map):
    data = world_dict(room_map)
    data["doors"] = [DOOR]
    data["people"], data["robots"][0]["camera"] = [], None
    data["robots"] = data["robots"][:1]    # Pepper alone: the Penguin's scans are not checked
    data["robots"][0]["pose"] = [4.0, 9.0, 0.0]
    data["robots"][0]["lasers"][0]["seed"] = 7
    return World(load_world_config(write_world(tmp_path, data), LASER_DIR), cache_dir=None)


def test_box_ranges_match_hand_calculation():
    ranges = box_ranges(0.0, 0.0, np.array([0.0, math.pi / 4, math.pi, math.pi / 2]),
                        [(1.0, -1.0, 2.0, 1.0), (-0.5, 3.0, 0.5, 4.0)])
    assert ranges == pytest.approx([1.0, math.sqrt(2.0), math.inf, 3.0])
    assert box_ranges(1.5, 0.0, np.array([0.3]), [(1.0, -1.0, 2.0, 1.0)])[0] == 0.0


def test_closed_door_is_seen_by_the_laser_and_open_again_is_not(door_world):
    laser, pose = door_world.robot("pepper").lasers[0], (4.0, 9.0, 0.0)
    ahead = len(laser.angles) // 2   # beam 22 of 45 points along +x
    assert laser.true_ranges(pose, (), door_world.closed_boxes)[ahead] == math.inf  # gap, > 1.5 m
    door_world.set_door("east", True)
    assert door_world.closed_boxes == [(5.0, 8.0, 5.2, 9.9)]
    assert laser.true_ranges(pose, (), door_world.closed_boxes)[ahead] == pytest.approx(1.0)
    door_world.step(0.1)   # the scan the world publishes carries the door too (noise 0.02 m)
    assert door_world.robot("pepper").scans[0].ranges[ahead] == pytest.approx(1.0, abs=0.1)
    door_world.set_door("east", False)
    assert laser.true_ranges(pose, (), door_world.closed_boxes)[ahead] == math.inf


def drive_east(world, seconds):
    for _ in range(int(seconds / 0.05)):
        world.set_twist("pepper", 0.5, 0.0, 0.0)
        world.step(0.05)
    return world.robot("pepper").state.pose[0]


def test_closed_door_stops_the_robot_and_an_open_one_lets_it_through(door_world, tmp_path,
                                                                    room_map):
    door_world.set_door("east", True)
    stopped_x = drive_east(door_world, 6.0)
    assert 4.5 < stopped_x < 5.0 - 0.3 + 0.05     # radius 0.3 m before the door leaf
    door_world.set_door("east", False)
    assert drive_east(door_world, 4.0) > 5.2 + 0.3


def test_unknown_door_and_bad_door_box_are_clear_errors(door_world, tmp_path, room_map):
    with pytest.raises(KeyError, match="no door named 'west' .doors: east."):
        door_world.set_door("west", True)
    data = world_dict(room_map)
    data["doors"] = [{"name": "east", "box": [5.2, 8.0, 5.0, 9.9]}]
    with pytest.raises(WorldError, match=r"doors\[0\]: box needs x1 > x0"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


@pytest.mark.parametrize("edit, message", [
    (lambda d: d["people"][0].update(raduis=0.3),
     r"world\.yaml: people\[0\]: unknown key 'raduis' \(did you mean 'radius'\?\)"),
    (lambda d: d.update(robot=[]),
     r"world\.yaml: unknown key 'robot' \(did you mean 'robots'\?\)"),
    (lambda d: d["robots"][0].update(radious=0.3),
     r"world\.yaml: robots\[0\]: unknown key 'radious' \(did you mean 'radius'\?\)"),
    (lambda d: d["robots"][0]["lasers"][0].update(raycats="table"),
     r"world\.yaml: robots\[0\]\.lasers\[0\]: unknown key 'raycats' \(did you mean 'raycast'\?\)"),
    (lambda d: d["robots"][0]["camera"]["top"].update(tilts=0.1),
     r"world\.yaml: robots\[0\]\.camera\.top: unknown key 'tilts' \(did you mean 'tilt'\?\)"),
    (lambda d: d["robots"][1]["odometry"].update(alpha_rot_rott=0.1),
     r"world\.yaml: robots\[1\]\.odometry: unknown key 'alpha_rot_rott' "
     r"\(did you mean 'alpha_rot_rot'\?\)"),
    (lambda d: d["people"][0]["schedule"][0].update(posure="lying"),
     r"world\.yaml: people\[0\]\.schedule\[0\]: unknown key 'posure' "
     r"\(did you mean 'posture'\?\)"),
    (lambda d: d["people"][0].update(shirt_colour={"joint1": [1, 2, 3], "joint2": [1, 2, 3],
                                                     "joint5": [1, 2, 3], "joint3": [1, 2, 3]}),
     r"world\.yaml: people\[0\]\.shirt_colour: unknown key 'joint3' \(did you mean 'joint5'\?\)"),
    (lambda d: d["objects"][3].update(hight=0.9),
     r"world\.yaml: objects\[3\]: unknown key 'hight' \(valid keys: name, label, pose, "
     r"elevation, size\)"),
    (lambda d: d.update(doors=[{"name": "d", "box": [1, 1, 2, 2], "close": True}]),
     r"world\.yaml: doors\[0\]: unknown key 'close' \(did you mean 'closed'\?\)"),
])
def test_unknown_key_names_file_field_and_nearest_key(tmp_path, room_map, edit, message):
    data = world_dict(room_map)
    edit(data)
    with pytest.raises(WorldError, match=message):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


def test_person_radius_and_walking_speed_are_world_keys(tmp_path, room_map):
    data = world_dict(room_map)
    data["people"][0].update(radius=0.3, walking_speed=1.2)
    person = load_world_config(write_world(tmp_path, data), LASER_DIR).people[0]
    assert (person.radius, person.walking_speed) == (0.3, 1.2)
    data["people"][0]["radius"] = 0
    with pytest.raises(WorldError, match=r"person 'Bob'\.radius: must be > 0, got 0"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


@pytest.mark.parametrize("world_file", sorted(
    str(p.relative_to(REPO)) for p in list((REPO / "config" / "worlds").glob("*.yaml"))
    + list((REPO / "src").glob("*/worlds/*.yaml"))))
def test_every_shipped_world_loads(world_file):
    config = load_world_config(REPO / world_file, LASER_DIR)
    assert config.robots


def calibrated(data):
    data["robots"][0]["camera"]["detection"] = {
        "model": "calibrated", "calibration": str(REPO / "config" / "camera_calibration.yaml")}
    return data


def test_lighting_zones_name_the_room_a_point_is_in(tmp_path, room_map):
    data = calibrated(world_dict(room_map))
    data["lighting"] = [{"name": "den", "box": [0.0, 0.0, 5.0, 4.0], "condition": "dim"}]
    config = load_world_config(write_world(tmp_path, data), LASER_DIR)
    assert config.lighting_at(2.0, 3.0) == "dim"
    assert config.lighting_at(6.0, 3.0) == "daylight"
    frame = World(config, cache_dir=None).camera_frame("pepper")
    assert all(obj.label for obj in frame.objects)


@pytest.mark.parametrize("change, message", [
    ({"lighting": [{"name": "den", "box": [0, 0, 5, 4], "condition": "candle"}]},
     "condition 'candle' is not a lighting row of .*camera_calibration.yaml"),
    ({"lighting": [{"name": "den", "box": [5, 0, 0, 4], "condition": "dim"}]},
     "box must have x0 < x1"),
    ({"lighting": [{"name": "den", "box": [0, 0, 5, 4], "conditon": "dim"}]},
     "did you mean 'condition'"),
])
def test_bad_lighting_is_a_clear_error(tmp_path, room_map, change, message):
    data = {**calibrated(world_dict(room_map)), **change}
    with pytest.raises(WorldError, match=message):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


def test_calibrated_camera_needs_a_readable_table(tmp_path, room_map):
    data = world_dict(room_map)
    data["robots"][0]["camera"]["detection"] = {"model": "calibrated"}
    with pytest.raises(WorldError, match="needs 'calibration'"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)
    data["robots"][0]["camera"]["detection"] = {"model": "calibrated", "calibration": "no.yaml"}
    with pytest.raises(WorldError, match="no.yaml.*scripts/calibrate_camera"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)
    data["robots"][0]["camera"]["detection"] = {"model": "perfect"}
    with pytest.raises(WorldError, match="model must be 'calibrated' or 'ideal'"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


def test_a_base_worlds_calibration_stays_relative_to_the_base(tmp_path, room_map):
    base_dir = tmp_path / "base"
    base_dir.mkdir()
    (base_dir / "table.yaml").write_text((REPO / "config" / "camera_calibration.yaml").read_text())
    data = world_dict(room_map)
    data["robots"][0]["camera"]["detection"] = {"model": "calibrated",
                                                "calibration": "table.yaml"}
    (base_dir / "base.yaml").write_text(yaml.safe_dump(data))
    derived = tmp_path / "derived.yaml"
    derived.write_text(yaml.safe_dump({"base": "base/base.yaml"}))
    config = load_world_config(derived, LASER_DIR)
    assert config.robots[0].camera.calibration.path.endswith("base/table.yaml")


def test_a_person_changes_clothes_where_the_entry_takes_her(tmp_path, room_map):
    data = world_dict(room_map)
    data["robots"] = data["robots"][:1]
    data["people"][0]["schedule"][0]["shirt_colour"] = {
        "joint1": [20, 20, 20], "joint2": [25, 25, 25], "joint5": [30, 30, 30]}
    world = World(load_world_config(write_world(tmp_path, data), LASER_DIR), cache_dir=None)
    bob = world.people[0]
    for _ in range(int(2.0 / 0.05)):         # on the way: still the blue shirt
        world.step(0.05)
    assert bob.shirt_colour == ((35, 70, 190),) * 3
    for _ in range(int(8.0 / 0.05)):
        world.step(0.05)
    assert bob.shirt_colour == ((20, 20, 20), (25, 25, 25), (30, 30, 30))
    data["people"][0]["schedule"][0]["shirt_colour"] = [300, 0, 0]
    with pytest.raises(WorldError, match=r"schedule\[0\].*shirt_colour must be"):
        load_world_config(write_world(tmp_path, data), LASER_DIR)


def test_a_seated_person_holds_things_on_the_table_in_front_not_under_it(tmp_path, room_map):
    """Bob sits at a 0.75 m table holding a cup: his wrists and the cup are above its top
    (skeleton.HAND_ABOVE_SURFACE); without the table they are at lap height."""
    from sim2d.skeleton import HAND_ABOVE_SURFACE, L_WRIST, R_WRIST, person_keypoints
    data = world_dict(room_map)
    bob = data["people"][0]
    bob.update(pose=[3.0, 3.0, 0.0], posture="sitting", holding="cup", schedule=[])
    data["objects"].append({"name": "table", "label": "dining table", "pose": [3.75, 3.0, 0.0],
                            "elevation": 0.0, "size": [0.8, 0.8, 0.75]})
    world = World(load_world_config(write_world(tmp_path, data), LASER_DIR), cache_dir=None)
    world.step(0.1)
    person = world.people[0]
    assert world.surface_under_hands(person) == pytest.approx(0.75)
    keypoints, hold = person_keypoints("sitting", person.pose, holding=True,
                                       surface=world.surface_under_hands(person))
    assert keypoints[[R_WRIST, L_WRIST], 2] == pytest.approx([0.75 + HAND_ABOVE_SURFACE] * 2)
    cup = world.objects["cup"]
    assert cup.elevation + cup.size[2] / 2.0 == pytest.approx(hold[2])
    lap, _ = person_keypoints("sitting", person.pose, holding=True)
    assert lap[R_WRIST, 2] < 0.75
    data["objects"].pop()                         # no table: nothing under the hands
    world = World(load_world_config(write_world(tmp_path, data), LASER_DIR), cache_dir=None)
    world.step(0.1)
    assert world.surface_under_hands(world.people[0]) is None
