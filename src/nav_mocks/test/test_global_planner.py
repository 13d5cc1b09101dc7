import math

import numpy as np
import pytest
from helpers import grid_from_rows, open_room
from floorplan.occupancy_map import OCCUPIED

from nav_mocks.costmap import Costmap, CostmapConfig
from nav_mocks.global_planner import GlobalPlanner, NoPath, PlannerConfig, nearest_free_cell

# a point robot: no inflation, so lengths can be computed by hand
POINT = CostmapConfig(robot_radius=0.0, footprint_padding=0.0, inflation_radius=0.0)


def test_plan_length_equals_hand_computed_optimum():
    grid = grid_from_rows(["..........",
                           "..........",
                           "######....",
                           ".........."], resolution=1.0)
    plan = GlobalPlanner(Costmap(grid, POINT), PlannerConfig(cost_factor=0.0)).plan(
        (0.5, 3.5), (0.5, 0.5))
    # cell (3,0) to (0,0) round the wall's end at column 5; a diagonal may not cut a blocked
    # corner, so: 6 straight to (3,6), 2 up to (1,6), one diagonal to (0,5), 5 straight to (0,0)
    expected = 6 + 2 + math.sqrt(2) + 5
    assert plan.length_m == pytest.approx(expected)
    assert tuple(plan.points[0]) == (0.5, 3.5) and tuple(plan.points[-1]) == (0.5, 0.5)


def test_unreachable_goal_raises_no_path():
    grid = grid_from_rows([".....",
                           ".###.",
                           ".#.#.",
                           ".###.",
                           "....."], resolution=1.0)
    with pytest.raises(NoPath, match="no path"):
        GlobalPlanner(Costmap(grid, POINT)).plan((0.5, 0.5), (2.5, 2.5))


def test_goal_in_obstacle_or_outside_map():
    grid = grid_from_rows(["...", ".#.", "..."], resolution=1.0)
    planner = GlobalPlanner(Costmap(grid, POINT))
    with pytest.raises(NoPath, match="in an obstacle"):
        planner.plan((0.5, 0.5), (1.5, 1.5))
    with pytest.raises(NoPath, match="outside the map"):
        planner.plan((0.5, 0.5), (5.0, 0.5))


def test_inflation_keeps_the_plan_off_walls_and_closes_narrow_gaps():
    grid = open_room(40, 20, resolution=0.05)          # 2.0 m x 1.0 m inside the walls
    grid.cells[:, 20] = OCCUPIED
    grid.cells[8:12, 20] = 0                           # a 0.2 m gap: narrower than the robot
    cfg = CostmapConfig(robot_radius=0.15, footprint_padding=0.0, inflation_radius=0.3)
    with pytest.raises(NoPath):
        GlobalPlanner(Costmap(grid, cfg)).plan((0.3, 0.5), (1.7, 0.5))
    grid.cells[4:16, 20] = 0                           # widen it to 0.6 m
    plan = GlobalPlanner(Costmap(grid, cfg)).plan((0.3, 0.5), (1.7, 0.5))
    costmap = Costmap(grid, cfg)
    clear = [costmap.cost_at(x, y) for x, y in plan.points]
    assert max(clear) < 253


def test_cost_factor_prefers_the_middle_of_a_corridor():
    grid = open_room(60, 16, resolution=0.05)          # a corridor 0.7 m wide
    cfg = CostmapConfig(robot_radius=0.1, footprint_padding=0.0, inflation_radius=0.4)
    planner = GlobalPlanner(Costmap(grid, cfg), PlannerConfig(cost_factor=3.0))
    plan = planner.plan((0.3, 0.35), (2.6, 0.35))
    assert np.abs(plan.points[:, 1] - 0.425).max() <= 0.1   # stays near the centre line


def test_unknown_space_is_crossed_only_when_not_lethal():
    grid = grid_from_rows(["..........",
                           "##????####",
                           ".........."], resolution=1.0)
    with pytest.raises(NoPath):
        GlobalPlanner(Costmap(grid, POINT)).plan((0.5, 0.5), (0.5, 2.5))
    open_unknown = CostmapConfig(robot_radius=0.0, footprint_padding=0.0, inflation_radius=0.0,
                                 unknown_is_lethal=False)
    plan = GlobalPlanner(Costmap(grid, open_unknown), PlannerConfig(cost_factor=0.0)).plan(
        (0.5, 0.5), (0.5, 2.5))
    # through the unknown gap at column 2; the walls' corners forbid every diagonal on the way:
    # 2 right, 2 down, 2 left
    assert plan.length_m == pytest.approx(6.0)


def test_tolerance_moves_a_blocked_goal_to_the_nearest_free_cell():
    grid = grid_from_rows(["......",
                           "......",
                           "...###",
                           "...###"], resolution=1.0)
    planner = GlobalPlanner(Costmap(grid, POINT), PlannerConfig(cost_factor=0.0))
    goal = (4.4, 2.4)                     # in cell (2, 4) of the wall block
    with pytest.raises(NoPath, match="in an obstacle"):
        planner.plan((0.5, 0.5), goal)                     # GetPlan's default tolerance 0
    with pytest.raises(NoPath, match="in an obstacle"):
        planner.plan((0.5, 0.5), goal, tolerance=0.5)      # no free cell centre within 0.5 m
    plan = planner.plan((0.5, 0.5), goal, tolerance=1.0)
    # free centres within 1 m in x and y: (3.5, 1.5) at 1.27 m, (4.5, 1.5) at 0.91 m: the latter
    assert tuple(plan.points[-1]) == (4.5, 1.5)
    # cell (0,0) -> (1,4): one diagonal then 3 straight; the first and last points are the
    # start (0.5, 0.5) and the cell centre (4.5, 1.5) themselves
    assert plan.length_m == pytest.approx(math.sqrt(2) + 3)


def test_tolerance_replaces_an_unreachable_goal_by_a_reachable_cell():
    grid = grid_from_rows([".......",
                           "...###.",
                           "...#.#.",
                           "...###."], resolution=1.0)
    planner = GlobalPlanner(Costmap(grid, POINT), PlannerConfig(cost_factor=0.0))
    with pytest.raises(NoPath, match="no path"):
        planner.plan((0.5, 0.5), (4.5, 2.5), tolerance=0.0)
    # the goal cell (2, 4) is free but enclosed; every other cell centre within 1 m of it in x
    # and y is a wall: nothing to move the goal to
    with pytest.raises(NoPath, match="no path"):
        planner.plan((0.5, 0.5), (4.5, 2.5), tolerance=1.0)
    plan = planner.plan((0.5, 0.5), (4.4, 2.5), tolerance=2.0)
    # reachable free centres within 2 m in x and y: column x = 2.5 (rows 0-3) and row y = 0.5
    # (x 2.5-5.5); the nearest is (2.5, 2.5) at 1.9 m ((4.5, 0.5) is 2.002 m away);
    # path cell (0, 0) -> (2, 2): two diagonals
    assert tuple(plan.points[-1]) == (2.5, 2.5)
    assert plan.length_m == pytest.approx(2 * math.sqrt(2))


def test_blocked_cells_open_the_footprint_of_a_robot_too_close_to_a_wall():
    # 1 m cells, a wall in column 0; radius 1.5, no padding: column 1 (1.0 from the wall cell
    # centres) is blocked, column 2 (2.0) is free. A robot at (1.6, 2.5) stands in column 1; its
    # footprint opens the column-1 cells of rows 1..3 (centres hypot(0.1, 1) = 1.005 <= 1.5
    # away), not rows 0 and 4 (2.0 away); the wall column stays lethal, so blocked
    grid = grid_from_rows(["#....."] * 5, resolution=1.0)
    config = CostmapConfig(robot_radius=1.5, footprint_padding=0.0, inflation_radius=1.5)
    planner = GlobalPlanner(Costmap(grid, config))
    far = planner.blocked_cells((4.5, 2.5))
    assert far[:, 0].all() and far[:, 1].all() and not far[:, 2:].any()
    near = planner.blocked_cells((1.6, 2.5))
    expected = far.copy()
    xs, ys = np.meshgrid(np.arange(6) + 0.5, np.arange(5) + 0.5)
    expected[(np.hypot(xs - 1.6, ys - 2.5) <= 1.5) & (np.arange(6)[None, :] > 0)] = False
    assert np.array_equal(near, expected)
    assert not near[1:4, 1].any() and near[0, 1] and near[4, 1] and near[:, 0].all()


def test_nearest_free_cell_stays_in_the_start_component_and_the_disc():
    grid = grid_from_rows([".....#....",
                           ".....#....",
                           "..###.....",
                           ".....#...."], resolution=1.0)
    blocked = grid.occupied_mask()
    # goal on the wall cell (2, 3): the nearest free cells (1, 3) and (3, 3) are reachable
    assert nearest_free_cell(grid, blocked, (0, 0), (3.5, 2.5), 1.0) in ((1, 3), (3, 3))
    # goal on (1, 5): (1, 6) on the far side of the wall is nearer than (1, 4)? both 1 m; a
    # start on the east side must get the east cell, a start on the west side the west one
    assert nearest_free_cell(grid, blocked, (0, 9), (5.5, 1.5), 1.0) == (1, 6)
    assert nearest_free_cell(grid, blocked, (0, 0), (5.5, 1.5), 1.0) == (1, 4)
    # a disc, not a square: the diagonal cell (2.5, 1.5) lies sqrt(2) m from (3.5, 2.5)
    closed = blocked.copy()
    closed[1, 3] = closed[3, 3] = closed[2, 5] = True
    assert nearest_free_cell(grid, closed, (0, 0), (3.5, 2.5), 1.2) is None
    assert nearest_free_cell(grid, closed, (0, 0), (3.5, 2.5), 1.5) in ((1, 2), (1, 4), (3, 2),
                                                                       (3, 4))
    with pytest.raises(ValueError, match="search radius -1"):
        nearest_free_cell(grid, blocked, (0, 0), (3.5, 2.5), -1)
