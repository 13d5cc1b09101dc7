import math

import numpy as np
import pytest
from helpers import integrate, open_room, synthetic_scan
from floorplan.occupancy_map import OCCUPIED

from nav_mocks.costmap import Costmap, CostmapConfig
from nav_mocks.dwa import DwaConfig
from nav_mocks.move_base_core import (ABORTED, ACTIVE, BACK_OUT, CLEAR, PREEMPTED, REJECTED, ROTATE,
                                      SUCCEEDED, ZERO, MoveBaseConfig, MoveBaseCore)

COSTMAP = CostmapConfig(robot_radius=0.2, footprint_padding=0.05, inflation_radius=0.5)
DT = 0.1


def two_rooms():
    """4 m x 3 m, a wall at x = 2 m with a 0.8 m door at y in [0.5, 1.3]; a closed cupboard."""
    grid = open_room(80, 60, resolution=0.05)
    grid.cells[:, 40] = OCCUPIED
    grid.cells[10:26, 40] = 0
    grid.cells[34:58, 50:78] = OCCUPIED           # closet: walls round a free 1.2 m x 1.1 m
    grid.cells[35:57, 51:77] = 0
    return grid


def run(core, pose, world=None, seconds=60.0, on_step=None):
    velocity, t, result = ZERO, 0.0, None
    while t < seconds:
        if world is not None:
            core.observe(synthetic_scan(world, core.costmap.grid, pose), pose)
        result = core.step(t, pose, velocity)
        if on_step:
            on_step(t, result)
        if result.status != ACTIVE:
            break
        pose = integrate(pose, result.cmd, DT)
        velocity, t = result.cmd, t + DT
    return result, pose


def make_core(grid=None, **config):
    return MoveBaseCore(Costmap(grid or two_rooms(), COSTMAP), MoveBaseConfig(**config),
                        DwaConfig(max_vel_y=0.3))


def test_reaches_a_goal_in_the_next_room():
    core = make_core()
    start = (0.6, 2.4, 0.0)
    assert core.start_goal((3.0, 0.6, math.pi / 2), 0.0, start) == (ACTIVE, "")
    result, pose = run(core, start)
    assert result.status == SUCCEEDED
    assert math.hypot(pose[0] - 3.0, pose[1] - 0.6) <= 0.1
    assert abs(math.remainder(pose[2] - math.pi / 2, 2 * math.pi)) <= 0.15


def test_rejects_goals_outside_the_map_or_in_a_wall_without_free_pose_near():
    core = make_core()
    status, reason = core.start_goal((5.0, 1.0, 0.0), 0.0, (0.6, 2.4, 0.0))
    assert status == REJECTED and "outside the map" in reason
    # the wall at x = 2.0..2.05 m: the nearest free cell (robot radius 0.2 + padding 0.05 off
    # the wall) lies about 0.25 m away, beyond a search radius of 0.1 m
    core = make_core(goal_search_radius=0.1)
    status, reason = core.start_goal((2.02, 2.5, 0.0), 0.0, (0.6, 2.4, 0.0))
    assert status == REJECTED
    assert reason == ("goal (2.02, 2.50) lies in an obstacle and no free pose reachable from "
                      "the robot lies within 0.10 m of it (goal_search_radius)")
    status, reason = make_core(goal_search_radius=0.0).start_goal((2.02, 2.5, 0.0), 0.0,
                                                                   (0.6, 2.4, 0.0))
    assert status == REJECTED and "within 0.00 m" in reason


def test_goal_in_a_wall_moves_to_the_nearest_free_pose_on_the_robots_side():
    core = make_core()                                  # goal_search_radius 1.0 m
    status, note = core.start_goal((2.02, 2.5, 1.0), 0.0, (0.6, 2.4, 0.0))
    assert status == ACTIVE
    assert note.startswith("goal (2.02, 2.50) lies in an obstacle: moved ")
    x, y, yaw = core.run.goal
    assert x < 2.0 and yaw == 1.0                       # the robot's room; heading kept
    assert 0.25 <= math.hypot(x - 2.02, y - 2.5) <= 0.35
    assert core.costmap.cost_at(x, y) < 253             # free for the planner
    assert core.run.requested == (2.02, 2.5, 1.0)
    result, pose = run(core, (0.6, 2.4, 0.0))
    assert result.status == SUCCEEDED and result.goal_note == note
    assert math.hypot(pose[0] - x, pose[1] - y) <= 0.1


def test_goal_closer_than_the_robot_radius_to_a_wall_is_moved_off_it():
    core = make_core()
    status, note = core.start_goal((1.9, 2.5, 0.0), 0.0, (0.6, 2.4, 0.0))   # 0.1 m from it
    assert status == ACTIVE
    assert "closer than the robot radius to an obstacle: moved" in note
    assert core.run.goal[0] < 1.9


def test_a_robot_close_to_a_wall_gets_a_moved_goal_a_plan_can_end_on():
    core = make_core()
    pose = (1.85, 2.5, 0.0)                             # 0.15 m from the wall: start blocked
    status, note = core.start_goal((2.02, 2.5, 0.0), 0.0, pose)
    assert status == ACTIVE and "moved" in note
    x, y, _ = core.run.goal
    assert core.costmap.cost_at(x, y) < 253             # not within the robot radius
    core.planner.plan(pose[:2], (x, y))                 # so the plan ends there


def test_person_on_the_goal_moves_it_while_driving_and_back_when_they_leave():
    grid = two_rooms()
    world = grid.occupied_mask().copy()
    rows, cols = np.ogrid[:60, :80]
    world[np.hypot(rows - 20, cols - 30) <= 4] = True   # a 0.2 m person on (1.5, 1.0)
    core = make_core(grid)
    goal = (1.5, 1.0, 0.0)
    assert core.start_goal(goal, 0.0, (0.6, 2.4, 0.0)) == (ACTIVE, "")   # not seen yet
    result, pose = run(core, (0.6, 2.4, 0.0), world=world)
    assert result.status == SUCCEEDED
    # the laser marks only the person's near side, so the first moves may land behind it;
    # every replan searches again and the goal ends on cells the laser saw to be clear
    assert result.goal_note.startswith(
        "goal (1.50, 1.00) is closer than the robot radius to an obstacle: moved ")
    assert 0.35 <= math.hypot(pose[0] - 1.5, pose[1] - 1.0) <= 1.0   # person 0.2 + robot 0.2
    assert pose[2] == pytest.approx(0.0, abs=0.15)                     # heading kept
    core.costmap.clear_obstacles()                      # the person left
    assert core.free_goal(goal, pose) == (goal, "")


def test_a_moved_goal_is_kept_while_it_stays_free():
    grid = two_rooms()
    world = grid.occupied_mask().copy()
    rows, cols = np.ogrid[:60, :80]
    world[np.hypot(rows - 20, cols - 30) <= 4] = True   # a 0.2 m person on (1.5, 1.0)
    core = make_core(grid)
    pose, requested = (0.6, 2.4, 0.0), (1.5, 1.0, 0.0)
    core.observe(synthetic_scan(world, grid, pose), pose)
    searched = core.free_goal(requested, pose)
    assert searched[1].startswith("goal (1.50, 1.00) is closer than the robot radius")
    free_elsewhere = ((1.0, 1.0, 0.0), "moved before")  # 0.5 m from the person: free
    assert searched[0][:2] != free_elsewhere[0][:2]
    assert core.free_goal(requested, pose, kept=free_elsewhere) == free_elsewhere
    on_the_person = ((1.5, 1.05, 0.0), "moved before")
    assert core.free_goal(requested, pose, kept=on_the_person) == searched


def test_person_on_the_goal_with_no_free_pose_near_aborts_naming_the_radius():
    grid = two_rooms()
    world = grid.occupied_mask().copy()
    rows, cols = np.ogrid[:60, :80]
    world[np.hypot(rows - 20, cols - 30) <= 4] = True
    core = make_core(grid, goal_search_radius=0.2)
    core.start_goal((1.5, 1.0, 0.0), 0.0, (0.6, 2.4, 0.0))
    result, _ = run(core, (0.6, 2.4, 0.0), world=world, seconds=120.0)
    assert result.status == ABORTED
    assert "goal (1.50, 1.00) is closer than the robot radius to an obstacle and no free " \
           "pose reachable from the robot lies within 0.20 m of it" in result.reason


@pytest.mark.parametrize("field, value", [
    ("planner_frequency", 0.0), ("planner_frequency", -1.0), ("planner_frequency", math.nan),
    ("controller_patience", math.inf), ("goal_search_radius", -0.5)])
def test_config_refuses_rates_and_radii_naming_the_parameter(field, value):
    with pytest.raises(ValueError, match=rf"parameter {field} must be a finite number "
                                         rf">=? 0 \[.*\], got {value}"):
        MoveBaseConfig(**{field: value}).validate()


def test_aborts_a_goal_that_cannot_be_reached():
    core = make_core()
    core.start_goal((3.175, 2.275, 0.0), 0.0, (0.6, 2.4, 0.0))   # inside the closet
    result, _ = run(core, (0.6, 2.4, 0.0))
    assert result.status == ABORTED and "no path" in result.reason


def test_cancel_stops_on_the_next_cycle():
    core = make_core()
    core.start_goal((3.0, 0.6, 0.0), 0.0, (0.6, 2.4, 0.0))
    commands = []

    def cancel_at_2s(t, result):
        commands.append(result.cmd)
        if t >= 2.0 and core.active:
            core.cancel()

    result, _ = run(core, (0.6, 2.4, 0.0), on_step=cancel_at_2s)
    assert result.status == PREEMPTED and result.cmd == ZERO
    assert any(abs(c[0]) > 0.1 for c in commands[:-1])   # it was moving before the cancel


def test_replans_around_an_obstacle_only_the_laser_sees():
    grid = two_rooms()
    world = grid.occupied_mask().copy()
    world[22:34, 16:28] = True                     # a box of 0.6 m on the straight line
    core = make_core(grid)
    core.start_goal((3.0, 1.4, 0.0), 0.0, (0.4, 1.4, 0.0))
    plans = []
    result, pose = run(core, (0.4, 1.4, 0.0), world=world,
                       on_step=lambda t, r: plans.append(r.new_plan) if r.new_plan else None)
    assert result.status == SUCCEEDED

    def through_box(plan):
        rows, cols = grid.world_to_cell(plan.points[:, 0], plan.points[:, 1])
        return world[rows, cols].any()

    # on the map alone the plan runs through the box; with the laser marks, every plan avoids it
    assert through_box(make_core(grid).make_plan((0.4, 1.4, 0.0), (3.0, 1.4, 0.0)))
    assert plans and not any(through_box(plan) for plan in plans)


def test_boxed_in_robot_aborts_after_recovery():
    grid = two_rooms()
    world = grid.occupied_mask().copy()
    rows, cols = np.ogrid[:60, :80]
    ring = np.hypot(rows - 30, cols - 12)
    world[(ring >= 7) & (ring <= 8)] = True          # a ring of radius 0.35-0.4 m around (0.6, 1.5)
    core = make_core(grid)
    core.start_goal((3.0, 0.6, 0.0), 0.0, (0.625, 1.525, 0.0))
    result, _ = run(core, (0.625, 1.525, 0.0), world=world, seconds=120.0)
    assert result.status == ABORTED and "after recovery" in result.reason
    assert core.run.history == [CLEAR, BACK_OUT, ROTATE]   # no line out of the ring: skipped


def test_back_out_leaves_a_wall_the_robot_is_wedged_against():
    # 0.25 m from the room's west wall (cell-centre distance), inside the collision radius
    # (0.2 + 0.0707 + 0.02 = 0.29 m): the back-out line of the 16 that gains most clearance
    # without coming closer to the wall is straight east, and the recovery drives it at 0.1 m/s.
    core = make_core()
    core.start_goal((3.0, 0.6, 0.0), 0.0, (0.27, 2.0, 0.0))
    assert core._back_out_direction((0.27, 2.0, 0.0)) == pytest.approx((1.0, 0.0))
    assert core._back_out_direction((0.27, 2.0, math.pi / 2)) == pytest.approx((1.0, 0.0),
                                                                               abs=1e-12)
    core.run.recovery_index = 1                      # clear_costmaps has been tried
    core._recover(core.run, 0.0, (0.27, 2.0, math.pi / 2), "test")
    cmd = core.step(0.0, (0.27, 2.0, math.pi / 2), ZERO).cmd
    assert cmd == pytest.approx((0.0, -0.1, 0.0), abs=1e-12)   # east, robot facing north


def test_continuous_clearance_keeps_only_hits_off_the_map():
    # robot at (1.0, 1.4) facing east; a 0.2 m box not on the map with its west face at x = 1.5
    # (cells 30..33, y rows 26..29: x in [1.50, 1.70], y in [1.30, 1.50]); the room wall at x = 0.05
    grid = two_rooms()
    world = grid.occupied_mask().copy()
    world[26:30, 30:34] = True
    core = make_core(grid)
    pose = (1.0, 1.4, 0.0)
    core.observe(synthetic_scan(world, grid, pose, beams=360), pose)
    hits = core._unmapped_hits()
    assert len(hits) > 0
    rows, cols = grid.world_to_cell(hits[:, 0], hits[:, 1])
    assert world[rows, cols].all() and not grid.occupied_mask()[rows, cols].any()
    local = core._local_clearance()
    # the beam straight ahead marches in 0.01 m steps and stops at 1.50 m: 0.50 m from the robot
    assert local.hit_distance(np.array([1.0]), np.array([1.4]))[0] == pytest.approx(0.50, abs=0.011)
    # the map's walls enter only through the contact region: west wall column 0 (centre
    # x = 0.025); a column k passes when 0.05 k >= 0.2 + 0.0707, i.e. k >= 6, so the region
    # starts at x = 0.30 and the depth at x = 1.0 is 0.70 (the door wall column 40 gives 0.75,
    # the south wall 1.1); the table is a lower bound within sqrt(2) fine cells (0.0071 m)
    depth = local.depth(np.array([1.0]), np.array([1.4]))[0]
    assert 0.70 - 0.0071 <= depth <= 0.70 + 1e-9
