import math

import numpy as np
import pytest
from helpers import grid_from_rows
from floorplan.occupancy_map import FREE, OCCUPIED, UNKNOWN

from nav_mocks.mapping import RevealedMap
from nav_mocks.scan_rays import Scan, beam_cells, hit_points

CORRIDOR = grid_from_rows(["##########",
                           "........#.",
                           "##########"], resolution=1.0)


def test_hit_points_in_map_frame():
    scan = Scan(np.array([0.0, math.pi / 2]), np.array([2.0, np.inf]), 0.1, 10.0)
    pts = hit_points(scan, (1.0, 1.0, math.pi / 2))
    assert pts == pytest.approx(np.array([[1.0, 3.0]]))   # the inf beam is no hit


def test_beam_cells_free_up_to_the_hit_cell():
    # laser at (0.5, 1.5) looking along +x; the wall cell (1, 8) starts at x = 8.0
    scan = Scan(np.array([0.0]), np.array([7.5]), 0.1, 20.0)
    free, hit = beam_cells(scan, (0.5, 1.5, 0.0), CORRIDOR, 20.0, 20.0)
    assert sorted(free[1].tolist()) == list(range(8)) and set(free[0].tolist()) == {1}
    assert (hit[0].tolist(), hit[1].tolist()) == ([1], [8])


def test_max_range_beam_clears_but_does_not_mark():
    scan = Scan(np.array([0.0]), np.array([4.0]), 0.1, 4.0)
    free, hit = beam_cells(scan, (0.5, 1.5, 0.0), CORRIDOR, 20.0, 20.0)
    assert sorted(free[1].tolist()) == [0, 1, 2, 3, 4] and len(hit[0]) == 0


def test_revealed_map_grows_with_scans():
    mapping = RevealedMap(CORRIDOR, max_range=20.0)
    assert (mapping.current().cells == UNKNOWN).all()
    scan = Scan(np.array([0.0, math.pi / 2, -math.pi / 2]), np.array([7.5, 0.5, 0.5]), 0.1, 20.0)
    assert mapping.integrate_scan(scan, (0.5, 1.5, 0.0)) == 11   # 8 free cells + 3 wall cells
    cells = mapping.current().cells
    assert (cells[1, :8] == FREE).all() and cells[1, 8] == OCCUPIED
    assert cells[0, 0] == OCCUPIED and cells[2, 0] == OCCUPIED and cells[1, 9] == UNKNOWN
    assert mapping.integrate_scan(scan, (0.5, 1.5, 0.0)) == 0
    assert mapping.explored_fraction() == pytest.approx(11 / 30)
