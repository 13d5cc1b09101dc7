"""Continuous clearance (clearance.py, costmap.admissible_cells / signed_depth_field) and the
DWA driving with it through a passage whose contact-free band is two cells wide."""
import math

import numpy as np
import pytest
from helpers import grid_from_rows
from sim2d.raycast import GridGeometry

from nav_mocks.clearance import OFF_GRID_DEPTH, ContactClearance
from nav_mocks.costmap import (Costmap, CostmapConfig, admissible_cells, obstacle_distance,
                               signed_depth_field)
from nav_mocks.dwa import DwaConfig, DwaController

RES = 0.05
RADIUS = 0.3


def corridor(free_rows, length=80):
    """Occupied rows 0 and free_rows + 1 around `free_rows` free rows, `length` columns."""
    rows = ["#" * length] + ["." * length] * free_rows + ["#" * length]
    return grid_from_rows(rows, resolution=RES)


def test_admissible_cells_beside_a_straight_wall():
    # wall in row 0: a cell k rows above has cell-centre distance 0.05 k; contact when
    # 0.05 k - 0.05 sqrt(2) < 0.3, i.e. k < 6 + sqrt(2) = 7.41: rows 8 and up pass
    grid = corridor(30)
    distance = obstacle_distance(grid.cells > 50) * RES
    ok = admissible_cells(distance, RADIUS, RES)
    column = ok[:, 40]
    assert list(np.nonzero(column)[0]) == list(range(8, 24))   # 31 - 8 = 23 from the far wall


def test_admissible_cells_match_the_simulators_contact_test():
    # an independent judge: sim2d's GridGeometry.clearance at every cell centre >= the radius
    rng = np.random.default_rng(3)
    cells = np.where(rng.random((40, 50)) < 0.02, 100, 0).astype(np.int8)
    grid = grid_from_rows(["." * 50] * 40, resolution=RES)
    grid.cells[:] = cells
    geometry = GridGeometry.from_map(grid)
    rows, cols = np.mgrid[:40, :50]
    xs, ys = grid.cell_to_world(rows, cols)
    expected = geometry.clearance(xs, ys) >= RADIUS
    distance = obstacle_distance(grid.cells > 50) * RES
    assert np.array_equal(admissible_cells(distance, RADIUS, RES), expected)


def test_signed_depth_field_bounds_the_distance_to_the_band_edges():
    # inside = columns 3..5 of 0.05 m cells: the band x in [0.15, 0.30] m; true depth of a
    # point is min(x - 0.15, 0.30 - x) inside, -(0.15 - x) or -(x - 0.30) outside
    inside = np.zeros((20, 10), dtype=bool)
    inside[:, 3:6] = True
    grid = grid_from_rows(["." * 10] * 20, resolution=RES)
    field = signed_depth_field(inside, 10)
    clearance = ContactClearance(field, 10, grid, RADIUS, np.zeros((0, 2)))
    xs = np.linspace(0.0005, 0.4995, 500)
    ys = np.full(xs.shape, 0.5)
    true = np.where((xs >= 0.15) & (xs < 0.30), np.minimum(xs - 0.15, 0.30 - xs),
                    -np.maximum(0.15 - xs, xs - 0.30))
    depth = clearance.depth(xs, ys)
    fine = RES / 10
    assert np.all(depth <= true + 1e-9)
    assert np.all(depth >= true - math.sqrt(2) * fine - 1e-9)
    # the centre x = 0.225: its fine cell's centre 0.2275 is 15 fine cells from the outside
    # cell centre 0.3025, less sqrt(2): 0.005 * (15 - 1.414) = 0.0679 m
    assert clearance.depth(np.array([0.225]), np.array([0.5]))[0] == \
        pytest.approx(0.005 * (15 - math.sqrt(2)), abs=1e-6)
    assert clearance.depth(np.array([-0.1]), np.array([0.5]))[0] == OFF_GRID_DEPTH


def test_clearance_is_the_smaller_of_the_contact_depth_and_the_hit_distance():
    inside = np.ones((20, 20), dtype=bool)
    inside[:, :2] = False          # outside region: x < 0.10 m
    grid = grid_from_rows(["." * 20] * 20, resolution=RES)
    clearance = ContactClearance(signed_depth_field(inside, 10), 10, grid, RADIUS,
                                 np.array([[0.80, 0.50]]))
    # at (0.60, 0.5): depth 0.50 (less at most 0.007) -> 0.80; the hit is 0.20 m away
    assert clearance.clearance(np.array([0.60]), np.array([0.5]))[0] == pytest.approx(0.20)
    # at (0.20, 0.5): depth 0.10 (fine-cell bound: 0.1 - 0.00707 <= . <= 0.1) vs hit 0.60
    value = clearance.clearance(np.array([0.20]), np.array([0.5]))[0]
    assert RADIUS + 0.1 - 0.00708 <= value <= RADIUS + 0.1
    limit = clearance.collision_radius(CostmapConfig(robot_radius=RADIUS), 0.03)
    assert limit == pytest.approx(0.33)


def drive_corridor(controller, local_for, offset, steps=150):
    """Drive along the corridor; the controller sees the true pose shifted by `offset` in y
    (a localisation error); returns the true trace."""
    truth, velocity, trace = (0.30, 0.45, 0.0), (0.0, 0.0, 0.0), []
    for _ in range(steps):
        estimate = (truth[0], truth[1] + offset, truth[2])
        trace.append(truth)
        if controller.at_goal_xy(estimate, (3.60, 0.45, 0.0)):
            break
        cmd = controller.best_command(estimate, velocity, local_for(estimate))
        if cmd is None:
            break
        dt = controller.config.control_period
        x, y, th = truth
        truth = (x + (cmd[0] * math.cos(th) - cmd[1] * math.sin(th)) * dt,
                 y + (cmd[0] * math.sin(th) + cmd[1] * math.cos(th)) * dt, th + cmd[2] * dt)
        velocity = cmd
    return np.array(trace)


@pytest.mark.parametrize("offset", [0.0, 0.02, -0.02])
def test_continuous_clearance_drives_a_two_cell_band_without_contact(offset):
    # walls in rows 0 and 17: row k passes the contact test when min(k, 17 - k) >= 8 (see the
    # straight-wall test), i.e. rows 8 and 9, y in [0.40, 0.50] m: a band two cells wide, 0.05 m
    # deep at its centre line y = 0.45. With a margin of 0.03 m the estimate may use a 2.6 cm
    # strip (less the 7 mm fine-cell bound); a constant 2 cm localisation error must not put
    # the true centre into a contact cell.
    grid = corridor(16)
    costmap = Costmap(grid, CostmapConfig(robot_radius=RADIUS, footprint_padding=0.1,
                                          inflation_radius=0.75))
    config = DwaConfig(max_vel_y=0.3, contact_margin=0.03)
    field = costmap.contact_depth(config.clearance_subdivision)
    controller = DwaController(config, costmap.config)
    controller.set_plan(np.column_stack((np.linspace(0.30, 3.60, 67), np.full(67, 0.45))))

    def local_for(pose):
        return ContactClearance(field, config.clearance_subdivision, grid, RADIUS,
                                np.zeros((0, 2)))

    trace = drive_corridor(controller, local_for, offset)
    assert controller.at_goal_xy(trace[-1], (3.60, 0.45, 0.0)) or \
        math.hypot(trace[-1][0] - 3.60, trace[-1][1] - 0.45) <= 0.1 + abs(offset)
    judge = GridGeometry.from_map(grid)        # sim2d's contact test on the true poses
    assert judge.clearance(trace[:, 0], trace[:, 1]).min() >= RADIUS
