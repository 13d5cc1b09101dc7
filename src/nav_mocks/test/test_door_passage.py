"""The dining-room door of the household map and the DWA's goal distance by way of the plan
(dwa.goal_distance_via_plan). With the straight-line distance to the local goal the robot stood
or crept at the door until a recovery wherever the plan folds round a wall
(docs/nav_mocks/RESULTS.md, "Door passage")."""
import math

import numpy as np
import pytest
from helpers import integrate, synthetic_scan
from floorplan.occupancy_map import FREE, OCCUPIED, OccupancyMap
from sim2d.raycast import GridGeometry

from nav_mocks import dwa
from nav_mocks.clearance import ContactClearance
from nav_mocks.costmap import Costmap, CostmapConfig
from nav_mocks.dwa import DwaConfig, DwaController, goal_distance_via_plan
from nav_mocks.move_base_core import ACTIVE, SUCCEEDED, ZERO, MoveBaseConfig, MoveBaseCore

RES = 0.05
# config/nav_mocks.yaml's values for the household Pepper
COSTMAP = CostmapConfig(robot_radius=0.3, footprint_padding=0.1, inflation_radius=0.75)
PEPPER = dict(max_vel_x=0.5, max_vel_y=0.3, max_vel_theta=1.5, acc_lim_x=0.5, acc_lim_y=0.5,
              acc_lim_theta=2.0, sim_granularity=0.05, contact_margin=0.03)
ALLEY_SIDE, DINING = (3.4, 6.5, math.pi), (1.4, 7.0, 0.0)


def dining_corner():
    """4 m x 3 m at 0.05 m, origin (0, 4.5): the household's dining table (x 0.90-1.90,
    y 5.30-6.30) and the wall at x 2.75-2.85 with the door at y 5.40-6.30, as in
    maps/household.yaml; the alley east of the wall."""
    cells = np.full((60, 80), FREE, dtype=np.int8)
    cells[0, :] = cells[-1, :] = cells[:, 0] = cells[:, -1] = OCCUPIED
    cells[16:36, 18:38] = OCCUPIED
    cells[:, 55:57] = OCCUPIED
    cells[18:36, 55:57] = FREE
    return OccupancyMap(cells=cells, resolution=RES, origin=(0.0, 4.5, 0.0))


def test_goal_distance_via_plan_by_hand():
    segment = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])   # east 1 m, then north 1 m
    points = np.array([[0.2, 0.1], [1.1, 0.4], [1.0, 1.0]])
    # nearest plan points (0, 0), (1, 0) and (1, 1); plan length left 2, 1 and 0
    expected = [math.hypot(0.2, 0.1) + 2.0, math.hypot(0.1, 0.4) + 1.0, 0.0]
    assert goal_distance_via_plan(points, segment) == pytest.approx(expected)


def folded_plan_command(monkeypatch, straight_line):
    """The DWA's first command at rest, facing west, on a plan that runs 1 m south, 1.5 m
    west (behind a wall) and 1 m north: the local goal lies 1.5 m west, level with the robot."""
    if straight_line:
        monkeypatch.setattr(dwa, "goal_distance_via_plan",
                            lambda points, segment: np.hypot(*(points - segment[-1]).T))
    legs = [np.column_stack((np.full(21, 3.0), np.linspace(6.5, 5.5, 21))),
            np.column_stack((np.linspace(3.0, 1.5, 31), np.full(31, 5.5))),
            np.column_stack((np.full(21, 1.5), np.linspace(5.5, 6.5, 21)))]
    controller = DwaController(DwaConfig(**PEPPER, local_goal_distance=3.5), COSTMAP)
    controller.set_plan(np.vstack(legs))
    grid = OccupancyMap(cells=np.zeros((100, 100), dtype=np.int8), resolution=RES,
                        origin=(0.0, 4.0, 0.0))
    costmap = Costmap(grid, COSTMAP)
    clearance = ContactClearance(costmap.contact_depth(10), 10, grid, COSTMAP.robot_radius,
                                 np.zeros((0, 2)))
    return controller.best_command((3.0, 6.5, math.pi), ZERO, clearance)


def test_a_plan_folded_round_a_wall_is_followed_from_rest(monkeypatch):
    vx, vy, _ = folded_plan_command(monkeypatch, straight_line=False)
    # facing west, the base's +y axis points south: the robot starts along the plan
    assert vy > 0.0 and abs(vx) < vy


def test_the_straight_line_goal_distance_holds_the_robot_still(monkeypatch):
    # the former term: moving south takes the robot away from the local goal, so a rotation in
    # place (no translation) scores best
    vx, vy, _ = folded_plan_command(monkeypatch, straight_line=True)
    assert vx == 0.0 and vy == 0.0


def drive(core, start, goal, seconds=60.0, dt=0.1):
    """The move_base core on the true pose with a reference laser; (status, time [s],
    true poses, recoveries)."""
    grid = core.costmap.grid
    world = grid.occupied_mask()
    pose, velocity, t, trace = start, ZERO, 0.0, [start]
    core.start_goal(goal, 0.0, pose)
    result = None
    while t < seconds:
        core.observe(synthetic_scan(world, grid, pose, beams=45, max_range=1.5), pose)
        result = core.step(t, pose, velocity)
        if result.status != ACTIVE:
            break
        pose = integrate(pose, result.cmd, dt)
        velocity, t = result.cmd, t + dt
        trace.append(pose)
    return result.status, t, np.array(trace), list(core.run.history)


def test_alley_to_dining_room_through_the_door_without_recovery():
    grid = dining_corner()
    core = MoveBaseCore(Costmap(grid, COSTMAP), MoveBaseConfig(), DwaConfig(**PEPPER))
    status, seconds, trace, recoveries = drive(core, ALLEY_SIDE, DINING)
    # 4.3 m of plan at up to 0.5 m/s: about 12 s here; a stall costs at least the 10 s
    # oscillation timeout and a recovery
    assert status == SUCCEEDED and recoveries == [] and seconds < 20.0
    judge = GridGeometry.from_map(grid)         # sim2d's contact test on the true poses
    assert judge.clearance(trace[:, 0], trace[:, 1]).min() >= COSTMAP.robot_radius


def test_the_former_scoring_stalls_at_the_same_door(monkeypatch):
    monkeypatch.setattr(dwa, "goal_distance_via_plan",
                        lambda points, segment: np.hypot(*(points - segment[-1]).T))
    grid = dining_corner()
    core = MoveBaseCore(Costmap(grid, COSTMAP), MoveBaseConfig(), DwaConfig(**PEPPER))
    status, seconds, _, recoveries = drive(core, ALLEY_SIDE, DINING)
    assert recoveries != [] and seconds > 20.0
