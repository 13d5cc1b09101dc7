"""Random training floors: reproducible, closed, corridors clear, doors narrower than branches."""
import numpy as np
import pytest

from semantic_nav.floor_generator import FloorGeneratorConfig, random_floor
from sim2d.blueprint import rect_cells
from sim2d.occupancy_map import FREE, OCCUPIED

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
