"""People never block the home: world files whose people cut places apart are refused."""
import pytest
import yaml
from sim2d_fixtures import LASER_DIR, REPO

from floorplan.occupancy_map import load_map
from sim2d.passage_check import PassageCheck
from floorplan.semantic_graph import load_graph
from sim2d.world_config import WorldError, load_world_config

WORLDS = REPO / "config" / "worlds"
HOUSEHOLD_MAP = REPO / "maps" / "household.yaml"
HOUSEHOLD_GRAPH = REPO / "maps" / "household.graph.yaml"


def household_world(tmp_path, person_pose, schedule_pose=None):
    """The household map and graph, Pepper (radius 0.3 m) and one person, Eve, written to a file."""
    eve = {"name": "Eve", "shirt_colour": [10, 20, 30], "pose": person_pose}
    if schedule_pose is not None:
        eve["schedule"] = [{"time": 30.0, "pose": schedule_pose, "via": [[3.4, 3.2]]}]
    data = {"map": str(HOUSEHOLD_MAP), "graph": str(HOUSEHOLD_GRAPH),
            "robots": [{"name": "pepper", "drive": "holonomic", "radius": 0.3,
                        "pose": "charging_place"}],
            "people": [eve]}
    path = tmp_path / "eve.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_person_in_the_dining_room_doorway_is_refused(tmp_path):
    # maps/blueprints/household.yaml: the doorway spans y 5.4..6.3 in the wall x = 2.8; its 0.9 m
    # leave 0.2 m either side of a 0.25 m-radius person at its middle, less than Pepper's 0.6 m
    path = household_world(tmp_path, [1.2, 1.35, 0.0], schedule_pose=[2.8, 5.85, 0.0])
    with pytest.raises(WorldError) as error:
        load_world_config(path, LASER_DIR)
    message = str(error.value)
    assert str(path) in message
    assert "person 'Eve' schedule pose at 30 s (2.80, 5.85)" in message
    assert "between places 'alley' and 'dining_room'" in message


def test_person_on_the_dining_room_side_of_the_doorway_is_refused(tmp_path):
    # the old household.yaml eat pose, in the 0.85 m between the dining table (x <= 1.9) and the
    # doorway's wall (x >= 2.75): the person leaves gaps of 0.1 m and 0.25 m, Pepper needs 0.6 m
    path = household_world(tmp_path, [2.25, 5.8, 3.14159])
    with pytest.raises(WorldError, match=r"person 'Eve' pose \(2.25, 5.80\) blocks the only way "
                                         r"between places 'alley' and 'dining_room'"):
        load_world_config(path, LASER_DIR)


def test_person_in_the_alley_cuts_the_north_rooms_off(tmp_path):
    # the alley is 1.1 m wide between its walls (x 2.85..3.95): 0.5 m of person + 0.6 m of robot
    path = household_world(tmp_path, [3.4, 8.0, 1.5708])
    with pytest.raises(WorldError, match=r"between places 'alley' and '(office|bedroom)'"):
        load_world_config(path, LASER_DIR)


def test_person_on_a_place_pose_is_refused_naming_the_place(tmp_path):
    # 0.22 m from welcome's pose (5.2, 2.0): the robot's goal there is inside the person
    path = household_world(tmp_path, [5.3, 2.2, 0.0])
    with pytest.raises(WorldError, match="stands on place 'welcome'"):
        load_world_config(path, LASER_DIR)


@pytest.mark.parametrize("pose", [[1.4, 2.5, 0.0],      # living room, between sofa and TV
                                  [5.6, 7.1, 2.45],     # bedroom, by the chair
                                  [1.4, 4.95, 1.57]])   # south side of the dining table
def test_person_in_a_room_is_accepted(tmp_path, pose):
    world = load_world_config(household_world(tmp_path, pose), LASER_DIR)
    assert world.people[0].pose == tuple(pose)


def test_blockage_names_the_graph_edge_first():
    # the doorway cuts dining_room off from all six other places; alley-dining_room is an edge
    graph = load_graph(HOUSEHOLD_GRAPH)
    check = PassageCheck(load_map(HOUSEHOLD_MAP), graph.places, graph.edges, robot_radius=0.3)
    blockage = check.blockage(2.8, 5.85)
    assert blockage.pairs[0] == ("alley", "dining_room")
    assert len(blockage.pairs) == 6 and all("dining_room" in pair for pair in blockage.pairs)
    assert blockage.covered == []


def test_a_thinner_robot_passes_where_pepper_cannot():
    # alley 1.1 m wide, person at x = 3.15 (0.3 m from the west wall's face): a gap of
    # 3.95 - 3.40 = 0.55 m on the east side; Pepper needs 0.6 m, a 0.2 m robot 0.4 m
    graph = load_graph(HOUSEHOLD_GRAPH)
    grid = load_map(HOUSEHOLD_MAP)
    assert PassageCheck(grid, graph.places, graph.edges, 0.3).blockage(3.15, 8.0) is not None
    assert PassageCheck(grid, graph.places, graph.edges, 0.2).blockage(3.15, 8.0) is None


@pytest.mark.parametrize("world", sorted(WORLDS.glob("*.yaml")), ids=lambda p: p.name)
def test_shipped_worlds_load(world):
    config = load_world_config(world, LASER_DIR)
    assert config.map_path.is_file()
