"""Route oracle against hand-annotated goals on every office floor in maps/, and bad input."""
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from semantic_nav.instruction_classes import CLASS_IDS
from semnav_learning.route_oracle import (OracleConfig, OracleError, RouteOracle, counting_matters,
                                       goal_branch, one_side_branch)
from floorplan.blueprint import render_blueprint
from floorplan.occupancy_map import load_map
import rospkg
from tamp_resources import resource

ROOT = resource()
FIXTURES = Path(rospkg.RosPack().get_path("semnav_learning")) / "fixtures"
EXPECTED = yaml.safe_load((FIXTURES /
                           "oracle_expected_goals.yaml").read_text())
CASES = [(floor, i, label) for floor, starts in EXPECTED.items()
         for i, entry in enumerate(starts) for label in CLASS_IDS]


@pytest.fixture(scope="module")
def oracles():
    return {floor: RouteOracle(load_map(ROOT / "maps" / f"{floor}.yaml")) for floor in EXPECTED}


@pytest.fixture(scope="module")
def computed(oracles):
    out = {}
    for floor, starts in EXPECTED.items():
        for i, entry in enumerate(starts):
            x, y, yaw = entry["start"]
            out[floor, i] = oracles[floor].goals((x, y, math.radians(yaw)))
    return out


def test_fixture_covers_every_floor_in_maps():
    floors = {p.stem for p in (ROOT / "maps").glob("*.yaml") if ".graph" not in p.name}
    assert floors and floors <= set(EXPECTED)
    assert all(len(starts) >= 3 for starts in EXPECTED.values())


@pytest.mark.parametrize("floor,index,label", CASES)
def test_oracle_matches_hand_annotation(computed, floor, index, label):
    expected = EXPECTED[floor][index]["goals"][label]
    goal = computed[floor, index][label]
    if expected == "n/a":
        assert goal is None, f"expected not applicable, oracle says {goal and goal.pose}"
        return
    assert goal is not None, "oracle says not applicable"
    x, y, yaw = goal.pose
    assert math.hypot(x - expected[0], y - expected[1]) <= 0.25, (x, y)
    assert abs(math.remainder(yaw - math.radians(expected[2]), 2 * math.pi)) <= math.radians(10)
    assert goal.contains(expected[0], expected[1], math.radians(expected[2]))


def _grid(walls, size=(12.0, 8.0), doors=()):
    return render_blueprint({"size": list(size), "resolution": 0.05, "wall_thickness": 0.2,
                             "walls": walls, "doors": list(doors)})


def test_l_corner_of_a_small_blueprint():
    # corridor y 2..4 running east into an L corner that turns north at x 8..10
    grid = _grid([[0, 2, 10, 2], [0, 4, 8, 4], [8, 4, 8, 8], [10, 2, 10, 8]])
    oracle = RouteOracle(grid)
    goals = oracle.goals((1.0, 3.0, 0.0))
    assert goals[1].pose[:2] == pytest.approx((8.9, 3.0), abs=0.06)     # 9.9 - 1.0
    assert goals[3].pose == pytest.approx((9.0, 4.9, math.pi / 2), abs=0.06)
    assert goals[10].pose == pytest.approx(goals[3].pose)
    assert goals[2] is None and goals[9] is None and goals[6] is None


def test_door_is_a_side_opening_not_a_corner():
    grid = _grid([[0, 2, 12, 2], [0, 4, 12, 4]], doors=[[5.0, 3.8, 6.0, 4.2]])
    walk = RouteOracle(grid).walk((1.0, 3.0, 0.0))
    assert [(o.side, o.is_branch) for o in walk.openings] == [("left", False)]
    assert walk.openings[0].width == pytest.approx(1.0, abs=0.1)
    assert walk.corners == []


def test_slanted_start_heading_finds_the_corridor_axis():
    grid = _grid([[0, 2, 12, 2], [0, 4, 12, 4]])
    walk = RouteOracle(grid).walk((1.0, 2.6, math.radians(12)))
    assert walk.axis == pytest.approx(0.0, abs=math.radians(1))
    assert walk.origin[1] == pytest.approx(3.0, abs=0.05)


def test_corners_count_over_both_sides_not_only_the_turning_side():
    # office_comb's blueprint, walking north up its spine from the south end: branches west at
    # y = 10, east at 14, both at 18 (the crossroad), west at 24, east at 27
    walk = RouteOracle(load_map(ROOT / "maps" / "office_comb.yaml")).walk((18.0, 5.0, math.pi / 2))

    def along(branch):
        return None if branch is None else round(float(walk.point(branch.centre)[1]))

    assert [along(goal_branch(walk, label)) for label in (5, 6, 7, 8)] == [14, None, 18, 18]
    assert [along(one_side_branch(walk, label)) for label in (5, 6, 7, 8)] == [18, 18, 27, 24]
    assert [counting_matters(walk, label) for label in CLASS_IDS] == \
        [False] * 4 + [True, False, True, True, False, False]


def test_map_with_no_corridor_is_a_clear_error():
    grid = _grid([], size=(12.0, 12.0))          # one empty 12 m x 12 m hall
    with pytest.raises(OracleError, match="no corridor"):
        RouteOracle(grid).goals((6.0, 6.0, 0.0))


def test_start_in_a_wall_is_a_clear_error():
    grid = _grid([[0, 2, 12, 2], [0, 4, 12, 4]])
    with pytest.raises(OracleError, match="not free space"):
        RouteOracle(grid).goals((5.0, 2.0, 0.0))


def test_map_without_free_space_is_a_clear_error():
    grid = _grid([])
    grid.cells[:] = 100
    with pytest.raises(OracleError, match="no free cell"):
        RouteOracle(grid, OracleConfig())


def test_unknown_class_is_a_clear_error():
    oracle = RouteOracle(_grid([[0, 2, 12, 2], [0, 4, 12, 4]]))
    with pytest.raises(OracleError, match="unknown instruction class"):
        oracle.goal((1.0, 3.0, 0.0), 11)


def test_goal_region_contains():
    oracle = RouteOracle(_grid([[0, 2, 12, 2], [0, 4, 12, 4]]))
    goal = oracle.goal((1.0, 3.0, 0.0), 1)
    assert goal.contains(goal.pose[0] + 0.7, goal.pose[1], math.radians(40))
    assert not goal.contains(goal.pose[0] + 0.8, goal.pose[1], 0.0)
    assert not goal.contains(goal.pose[0], goal.pose[1], math.radians(50))
    assert np.isfinite(goal.pose).all()


def _rotated(grid, theta):
    """The grid rotated by theta about its centre (nearest cell, outside = wall), and the
    function that carries a pose of the original map into the rotated one."""
    res = grid.resolution
    h, w = grid.cells.shape
    c_old = np.array([w * res / 2, h * res / 2])
    size = int(math.ceil(math.hypot(w, h))) + 4
    c_new = np.full(2, size * res / 2)
    v, u = np.mgrid[0:size, 0:size]
    x, y = (u + 0.5) * res - c_new[0], (v + 0.5) * res - c_new[1]
    xs = math.cos(theta) * x + math.sin(theta) * y + c_old[0]
    ys = -math.sin(theta) * x + math.cos(theta) * y + c_old[1]
    col, row = np.floor(xs / res).astype(int), np.floor(ys / res).astype(int)
    inside = (row >= 0) & (row < h) & (col >= 0) & (col < w)
    cells = np.full((size, size), 100, dtype=np.int8)
    cells[inside] = grid.cells[row[inside], col[inside]]

    def carry(pose):
        dx, dy = pose[0] - c_old[0], pose[1] - c_old[1]
        return (math.cos(theta) * dx - math.sin(theta) * dy + c_new[0],
                math.sin(theta) * dx + math.cos(theta) * dy + c_new[1], pose[2] + theta)
    return type(grid)(cells=cells, resolution=res, origin=(0.0, 0.0, 0.0)), carry


@pytest.mark.parametrize("floor", sorted(EXPECTED))
@pytest.mark.parametrize("degrees", [30, -62])
def test_oracle_on_rotated_floors(floor, degrees):
    """Floors nobody has seen: the same buildings turned off the grid axes (stair-step walls)."""
    grid, carry = _rotated(load_map(ROOT / "maps" / f"{floor}.yaml"), math.radians(degrees))
    oracle = RouteOracle(grid)
    for entry in EXPECTED[floor]:
        x, y, yaw = entry["start"]
        goals = oracle.goals(carry((x, y, math.radians(yaw))))
        for label, expected in entry["goals"].items():
            if expected == "n/a":
                assert goals[label] is None, (entry["start"], label)
                continue
            ex, ey, eyaw = carry((expected[0], expected[1], math.radians(expected[2])))
            assert goals[label] is not None, (entry["start"], label)
            gx, gy, gyaw = goals[label].pose
            assert math.hypot(gx - ex, gy - ey) <= 0.3, (entry["start"], label)
            assert abs(math.remainder(gyaw - eyaw, 2 * math.pi)) <= math.radians(10)
