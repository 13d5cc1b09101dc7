"""Random training floors: reproducible, closed, corridors clear, doors narrower than branches,
doors straight ahead at corridor ends only where an office lies behind."""
import numpy as np
import pytest

from semnav_learning.floor_generator import (Corridor, FloorGeneratorConfig, end_doors,
                                          random_floor, side_branches)
from floorplan.blueprint import rect_cells
from floorplan.occupancy_map import FREE, OCCUPIED

CONFIG = FloorGeneratorConfig()
RES = CONFIG.resolution


def _runs(values):
    """Lengths of the runs of True in a 1-D boolean array."""
    padded = np.concatenate([[False], values, [False]]).astype(int)
    edges = np.flatnonzero(np.diff(padded))
    return edges[1::2] - edges[::2]


def test_same_seed_same_floor_other_seed_other_floor():
    a, _ = random_floor(7)
    b, _ = random_floor(7)
    c, _ = random_floor(8)
    assert np.array_equal(a.cells, b.cells)
    assert a.cells.shape != c.cells.shape or not np.array_equal(a.cells, c.cells)


@pytest.mark.parametrize("seed", range(6))
def test_floor_is_closed_and_corridors_are_clear(seed):
    grid, corridors = random_floor(seed)
    cells = grid.cells
    assert set(np.unique(cells)) <= {FREE, OCCUPIED}
    wall = int(round(CONFIG.wall / RES))
    for border in (cells[:wall], cells[-wall:], cells[:, :wall], cells[:, -wall:]):
        assert np.all(border == OCCUPIED)
    assert corridors, "a floor without corridors"
    for corridor in corridors:
        lo, hi = CONFIG.corridor_width
        assert lo <= corridor.width <= hi
        x0, y0, x1, y1 = corridor.rect()
        # the corridor itself minus the outer wall band it may end against
        inner = [max(x0, CONFIG.wall), max(y0, CONFIG.wall),
                 min(x1, grid.width * RES - CONFIG.wall), min(y1, grid.height * RES - CONFIG.wall)]
        assert np.all(cells[rect_cells(inner, RES, cells.shape)] == FREE)


@pytest.mark.parametrize("seed", range(6))
def test_openings_in_corridor_walls_are_doors_or_corridor_mouths(seed):
    """Walk the wall band beside every corridor: each gap is a door (0.8-1.1 m, narrower than
    the oracle's 1.3 m branches) or at least a corridor width (another corridor's mouth)."""
    grid, corridors = random_floor(seed)
    free = grid.cells == FREE
    doors = 0
    for corridor in corridors:
        x0, y0, x1, y1 = corridor.rect()
        for side in (-1, 1):
            if corridor.horizontal:
                y = (y1 + 0.5 * CONFIG.wall) if side > 0 else (y0 - 0.5 * CONFIG.wall)
                row = int(np.floor(y / RES))
                if not 0 <= row < free.shape[0]:
                    continue
                band = free[row, int(np.ceil(x0 / RES)):int(np.floor(x1 / RES))]
            else:
                x = (x1 + 0.5 * CONFIG.wall) if side > 0 else (x0 - 0.5 * CONFIG.wall)
                col = int(np.floor(x / RES))
                if not 0 <= col < free.shape[1]:
                    continue
                band = free[int(np.ceil(y0 / RES)):int(np.floor(y1 / RES)), col]
            for run in _runs(band[1:-1]) * RES:   # ends: the corridor's own end walls
                is_door = CONFIG.door_width[0] - 2 * RES <= run <= CONFIG.door_width[1] + 2 * RES
                is_mouth = run >= CONFIG.corridor_width[0] - 2 * RES
                assert is_door or is_mouth, f"gap of {run:.2f} m beside {corridor}"
                doors += is_door
    assert doors > 0


@pytest.mark.parametrize("length", [(3.0, 8.0), (3.0, 5.0)])
@pytest.mark.parametrize("seed", range(4))
def test_side_branches_leave_one_side_clear_of_other_mouths(seed, length):
    # a 40 m corridor along y = 10 (walls at 9 and 11) crossed by one at x = 20 (19..21)
    config = FloorGeneratorConfig(side_branch_rate=0.3, side_branch_length=length)
    main, cross = Corridor(True, 10.0, 0.0, 40.0, 2.0), Corridor(False, 20.0, 0.0, 20.0, 2.0)
    branches = side_branches(np.random.default_rng(seed), [main, cross], 40.0, 20.0, config)
    assert branches, "rate 0.3 on 60 m of corridor gave no branch"
    spans = [(19.0, 21.0)]
    for branch in branches:
        low, high = branch.centre - branch.width / 2, branch.centre + branch.width / 2
        if branch.horizontal:        # off the crossing corridor x 19..21
            assert branch.start == 21.0 or branch.end == 19.0
            continue
        assert branch.start == 11.0 or branch.end == 9.0          # one side of the wall only
        assert length[0] <= branch.end - branch.start <= length[1]
        assert all(high + 1.5 <= a or b + 1.5 <= low for a, b in spans), (branch, spans)
        spans.append((low, high))


def test_side_branches_keep_the_floor_closed_and_older_seeds_unchanged():
    plain, _ = random_floor(4)
    grid, corridors = random_floor(4, FloorGeneratorConfig(side_branch_rate=0.3))
    assert np.array_equal(random_floor(4, FloorGeneratorConfig(side_branch_rate=0.0))[0].cells,
                          plain.cells)
    wall = int(round(CONFIG.wall / RES))
    cells = grid.cells
    for border in (cells[:wall], cells[-wall:], cells[:, :wall], cells[:, -wall:]):
        assert np.all(border == OCCUPIED)
    assert len(corridors) > len(random_floor(4)[1])


def test_end_doors_open_straight_ahead_where_an_office_lies_behind():
    # a dead end at x = 12 (wall 12..12.2, an office beyond) and the map edge behind x = 0.2
    config = FloorGeneratorConfig(end_door_probability=1.0)
    shape = (int(10 / RES), int(20 / RES))
    corridor = Corridor(True, 5.0, 0.2, 12.0, 2.0)
    free = np.zeros(shape, dtype=bool)
    free[rect_cells(corridor.rect(), RES, shape)] = True
    rooms = np.zeros(shape, dtype=bool)
    rooms[rect_cells([12.2, 0.2, 19.8, 9.8], RES, shape)] = True
    free |= rooms
    doors = end_doors(free, rooms, [corridor], np.random.default_rng(3), config, RES)
    assert len(doors) == 1, doors
    x0, y0, x1, y1 = doors[0]
    assert x0 < 12.0 and x1 > 12.2                       # through the end wall
    assert CONFIG.door_width[0] <= y1 - y0 <= CONFIG.door_width[1]
    assert 4.0 + 0.1 <= y0 and y1 <= 6.0 - 0.1          # inside the corridor's width
    wall_column = free[:, int(12.1 / RES)]
    assert max(_runs(wall_column)) * RES == pytest.approx(y1 - y0, abs=2 * RES)
    # a crossing-only corridor (no longer than a corridor is wide) has no end of its own
    short = Corridor(True, 5.0, 10.0, 12.0, 2.0)
    assert not end_doors(free, rooms, [short], np.random.default_rng(3), config, RES)


def test_end_doors_keep_the_floor_closed_and_older_seeds_unchanged():
    plain, _ = random_floor(5)
    assert np.array_equal(random_floor(5, FloorGeneratorConfig(end_door_probability=0.0))[0]
                          .cells, plain.cells)
    grid, _ = random_floor(5, FloorGeneratorConfig(end_door_probability=1.0))
    assert not np.array_equal(grid.cells, plain.cells)
    wall = int(round(CONFIG.wall / RES))
    cells = grid.cells
    for border in (cells[:wall], cells[-wall:], cells[:, :wall], cells[:, -wall:]):
        assert np.all(border == OCCUPIED)
