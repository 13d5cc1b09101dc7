"""Free-space skeleton, junctions, dead ends, corridor network and start sampling."""
import math

import numpy as np
import pytest

from semnav_learning.floor_structure import (floor_structure, sample_corridor_starts,
                                          zhang_suen_skeleton)
from semnav_learning.route_oracle import OracleError, RouteOracle
from floorplan.blueprint import render_blueprint
from floorplan.occupancy_map import load_map
from tamp_resources import resource

ROOT = resource()


def _grid(walls, size, doors=()):
    return render_blueprint({"size": list(size), "resolution": 0.05, "wall_thickness": 0.2,
                             "walls": walls, "doors": list(doors)})


def test_skeleton_of_a_bar_is_its_centre_line():
    bar = np.zeros((9, 40), dtype=bool)
    bar[2:7, 3:37] = True
    skeleton = zhang_suen_skeleton(bar)
    rows, cols = np.nonzero(skeleton)
    assert set(rows) == {4}                       # one cell wide, on the middle row
    assert cols.min() <= 6 and cols.max() >= 33


def test_plus_shaped_corridors_have_one_junction_and_four_dead_ends():
    # two 1.8 m corridors crossing in the middle of a 12 m x 12 m floor
    walls = [[0, 5, 5, 5], [7, 5, 12, 5], [0, 7, 5, 7], [7, 7, 12, 7],
             [5, 0, 5, 5], [7, 0, 7, 5], [5, 7, 5, 12], [7, 7, 7, 12]]
    oracle = RouteOracle(_grid(walls, (12.0, 12.0)))
    structure = floor_structure(oracle.field, 0.3)
    junction_xy = [oracle.field.grid.cell_to_world(r, c) for r, c in structure.junctions]
    assert junction_xy and all(math.hypot(x - 6.0, y - 6.0) < 0.3 for x, y in junction_xy)
    ends = [oracle.field.grid.cell_to_world(r, c) for r, c in structure.dead_ends]
    corridor_ends = [e for e in ends if abs(e[0] - 6.0) < 0.1 or abs(e[1] - 6.0) < 0.1]
    assert len(corridor_ends) == 4


def test_room_behind_a_door_is_not_corridor_network():
    # corridor y 0..2 along a 16 m floor, a 6 m deep room above it behind a 1 m door
    grid = _grid([[0, 2, 16, 2]], (16.0, 8.0), doors=[[7.5, 1.8, 8.5, 2.2]])
    oracle = RouteOracle(grid)
    structure = floor_structure(oracle.field, 0.3)
    row, col = grid.world_to_cell(8.0, 1.0)
    assert structure.corridors[row, col]
    row, col = grid.world_to_cell(8.0, 5.0)
    assert not structure.corridors[row, col]


def test_starts_lie_on_corridor_centre_lines():
    grid = _grid([], (16.0, 2.0))     # one 16 m corridor, 1.8 m clear, centre line y = 1
    oracle = RouteOracle(grid)
    starts = sample_corridor_starts(oracle, floor_structure(oracle.field, 0.3), 12,
                                    np.random.default_rng(1))
    for x, y, yaw in starts:
        assert y == pytest.approx(1.0, abs=0.06)
        assert abs(math.sin(yaw)) < math.sin(math.radians(2))
    assert {round(math.cos(yaw)) for _, _, yaw in starts} == {-1, 1}   # both directions


def test_empty_hall_has_no_corridor_starts():
    oracle = RouteOracle(_grid([], (12.0, 12.0)))
    with pytest.raises(OracleError, match="corridor"):
        sample_corridor_starts(oracle, floor_structure(oracle.field, 0.3), 3,
                               np.random.default_rng(0), max_tries=30)


def test_office_floor_starts_are_in_corridors():
    oracle = RouteOracle(load_map(ROOT / "maps" / "office_crossroads.yaml"))
    starts = sample_corridor_starts(oracle, floor_structure(oracle.field, 0.3), 10,
                                    np.random.default_rng(2))
    for x, y, _ in starts:   # H corridor y 9.1..10.9 or V corridor x 14.1..15.9
        assert abs(y - 10.0) < 0.1 or abs(x - 15.0) < 0.1
