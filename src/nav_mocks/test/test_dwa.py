import math

import numpy as np
import pytest
from helpers import open_room

from nav_mocks.costmap import CostmapConfig
from nav_mocks.dwa import (DwaConfig, DwaController, LocalCostmap, contact_clearance,
                           fuse_scans, local_plan, rollout, sample_velocities,
                           velocity_window)

COSTMAP = CostmapConfig(robot_radius=0.2, footprint_padding=0.1, inflation_radius=0.5)
ROOM = open_room(80, 60, resolution=0.05)          # 4 m x 3 m


def test_dynamic_window_is_limited_by_acceleration_and_speed():
    cfg = DwaConfig(max_vel_x=0.5, acc_lim_x=2.0, max_vel_theta=1.0, acc_lim_theta=4.0,
                    control_period=0.1)
    window = velocity_window((0.45, 0.0, -0.9), cfg)
    assert window[0] == pytest.approx((0.25, 0.5))
    assert window[1] == (0.0, 0.0)                  # differential drive: no lateral speed
    assert window[2] == pytest.approx((-1.0, -0.5))


def test_samples_include_stop_and_lateral_for_holonomic():
    cfg = DwaConfig(max_vel_y=0.3, vx_samples=3, vy_samples=3, vth_samples=3)
    samples = sample_velocities((0.0, 0.0, 0.0), cfg)
    assert len(samples) == 27 and (np.abs(samples).sum(axis=1) == 0).any()
    assert samples[:, 1].max() == pytest.approx(0.2)   # 2 m/s^2 x 0.1 s


def test_rollout_straight_arc_and_lateral():
    cfg = DwaConfig(sim_time=1.0, sim_granularity=0.1)
    v = np.array([[0.5, 0.0, 0.0], [0.0, 0.3, 0.0], [0.5, 0.0, 1.0]])
    end = rollout((1.0, 1.0, math.pi / 2), v, cfg)[:, -1, :]
    assert end[0] == pytest.approx((1.0, 1.5, math.pi / 2))
    assert end[1] == pytest.approx((0.7, 1.0, math.pi / 2))
    # arc of radius 0.5 through 1 rad (Euler steps of 0.1 s, so within a few mm)
    assert end[2][:2] == pytest.approx((1.0 - 0.5 * (1 - math.cos(1.0)), 1.0 + 0.5 * math.sin(1.0)),
                                       abs=0.03)


def test_local_plan_starts_at_the_nearest_point():
    plan = np.column_stack((np.linspace(0, 5, 51), np.zeros(51)))
    segment, index = local_plan(plan, (2.02, 0.3, 0.0), 0, 1.0)
    assert index == 20 and segment[0, 0] == pytest.approx(2.0)
    assert segment[-1, 0] == pytest.approx(3.0)


def drive(controller, pose, goal, points, steps=120):
    velocity = (0.0, 0.0, 0.0)
    trace = [pose]
    for _ in range(steps):
        local = LocalCostmap(np.zeros(ROOM.cells.shape, bool) | (ROOM.cells > 50), ROOM, pose,
                             points, controller.config.local_window)
        cmd = controller.best_command(pose, velocity, local)
        if cmd is None or controller.at_goal_xy(pose, goal):
            break
        x, y, th = pose
        dt = controller.config.control_period
        pose = (x + (cmd[0] * math.cos(th) - cmd[1] * math.sin(th)) * dt,
                y + (cmd[0] * math.sin(th) + cmd[1] * math.cos(th)) * dt, th + cmd[2] * dt)
        velocity = cmd
        trace.append(pose)
    return pose, np.array(trace)


def test_follows_a_straight_plan_to_the_goal():
    controller = DwaController(DwaConfig(), COSTMAP)
    controller.set_plan(np.column_stack((np.linspace(0.5, 3.5, 61), np.full(61, 1.5))))
    pose, trace = drive(controller, (0.5, 1.5, 0.0), (3.5, 1.5, 0.0), np.zeros((0, 2)))
    assert controller.at_goal_xy(pose, (3.5, 1.5, 0.0))
    assert np.abs(trace[:, 1] - 1.5).max() < 0.05


def test_avoids_an_obstacle_seen_only_by_the_laser():
    controller = DwaController(DwaConfig(), COSTMAP)
    controller.set_plan(np.column_stack((np.linspace(0.5, 3.5, 61), np.full(61, 1.5))))
    # a 0.3 m box beside the plan at x = 2, not on the map: its near face is 0.2 m from the
    # plan, closer than the padded robot radius (0.3 m), so the robot must swerve to pass it
    box = np.array([(2.0 + dx, 1.85 + dy) for dx in np.linspace(-0.15, 0.15, 7)
                    for dy in np.linspace(-0.15, 0.15, 7)])
    pose, trace = drive(controller, (0.5, 1.5, 0.0), (3.5, 1.5, 0.0), box, steps=200)
    assert controller.at_goal_xy(pose, (3.5, 1.5, 0.0))
    gaps = np.hypot(trace[:, None, 0] - box[None, :, 0], trace[:, None, 1] - box[None, :, 1])
    # clearance is judged on 0.05 m cells: up to half a cell diagonal (0.035 m) is lost
    assert gaps.min() > COSTMAP.inscribed_radius - 0.05 * math.sqrt(2) / 2
    assert trace[:, 1].min() < 1.5 - 0.05          # it swerved away from the box


def test_boxed_in_robot_can_only_turn_in_place():
    controller = DwaController(DwaConfig(), COSTMAP)
    controller.set_plan(np.array([[1.0, 1.0], [2.0, 1.0]]))
    ring = np.array([(1.0 + 0.3 * math.cos(a), 1.0 + 0.3 * math.sin(a))
                     for a in np.linspace(0, 2 * math.pi, 60)])
    local = LocalCostmap(ROOM.cells > 50, ROOM, (1.0, 1.0, 0.0), ring, 5.0)
    cmd = controller.best_command((1.0, 1.0, 0.0), (0.0, 0.0, 0.0), local)
    assert cmd[0] == 0.0 and cmd[1] == 0.0
    ring = ring * 0.5 + 0.5                           # 0.15 m: already inside the robot radius
    local = LocalCostmap(ROOM.cells > 50, ROOM, (1.0, 1.0, 0.0), ring, 5.0)
    cmd = controller.best_command((1.0, 1.0, 0.0), (0.0, 0.0, 0.0), local)
    assert cmd[0] == 0.0 and cmd[1] == 0.0


def test_rotates_in_place_to_the_goal_yaw():
    controller = DwaController(DwaConfig(yaw_goal_tolerance=0.1), COSTMAP)
    cmd, done = controller.rotate_to((1.0, 1.0, 0.0), (1.0, 1.0, 1.0), (0.0, 0.0, 0.0))
    assert not done and cmd == (0.0, 0.0, pytest.approx(0.4))   # acceleration-limited
    assert controller.rotate_to((1.0, 1.0, 0.95), (1.0, 1.0, 1.0), (0.0, 0.0, 0.0))[1]


def test_contact_clearance_is_the_radius_plus_the_cell_bound():
    # a simulator or bumper on the same 0.05 m grid sees contact when the cell-centre distance
    # minus sqrt(2) cells falls below the radius: 0.3 + 0.0707 m, plus the 0.02 m margin
    assert contact_clearance(0.3, 0.05, 0.02) == pytest.approx(0.3 + 0.05 * math.sqrt(2) + 0.02)


def test_keeps_the_contact_clearance_when_the_padding_is_smaller():
    # radius 0.2 m without padding: inscribed 0.2 m, but on 0.05 m cells contact needs a
    # cell-centre clearance of 0.2 + 0.0707 (+ 0.02 margin) = 0.29 m. The plan runs 0.25 m from a
    # wall only the laser sees: the robot must leave the plan and keep 0.29 m (less half a cell
    # diagonal, 0.035 m, for where in its cell the robot centre lies).
    costmap = CostmapConfig(robot_radius=0.2, footprint_padding=0.0, inflation_radius=0.5)
    controller = DwaController(DwaConfig(), costmap)
    controller.set_plan(np.column_stack((np.linspace(0.5, 3.5, 61), np.full(61, 1.5))))
    wall = np.column_stack((np.linspace(1.5, 2.5, 41), np.full(41, 1.75)))
    local = LocalCostmap(ROOM.cells > 50, ROOM, (1.0, 1.5, 0.0), wall, 5.0)
    assert controller.collision_radius(local) == pytest.approx(0.2 + 0.05 * math.sqrt(2) + 0.02)
    pose, trace = drive(controller, (0.5, 1.5, 0.0), (3.5, 1.5, 0.0), wall, steps=200)
    assert controller.at_goal_xy(pose, (3.5, 1.5, 0.0))
    gaps = np.hypot(trace[:, None, 0] - wall[None, :, 0], trace[:, None, 1] - wall[None, :, 1])
    assert gaps.min() > 0.29 - 0.05 * math.sqrt(2) / 2


def test_fused_scans_ignore_a_hit_that_noise_moved_one_cell_closer():
    # the robot at cell (20, 20)'s centre; one obstacle 10 cells east (0.5 m) in scans A, one
    # cell closer (0.45 m, as 2 cm range noise can make it) in scan B; the room's walls are 1 m away
    robot = (1.025, 1.025)
    a, b = np.array([[1.525, 1.025]]), np.array([[1.475, 1.025]])

    def clearance(scans):
        local = LocalCostmap(ROOM.cells > 50, ROOM, robot + (0.0,), scans, 5.0)
        return float(local.clearance(np.array([robot[0]]), np.array([robot[1]]))[0])

    assert clearance(b) == pytest.approx(0.45)              # one scan: its own hits
    assert clearance([a, b, a]) == pytest.approx(0.5)       # B is outvoted
    assert clearance([b, b, a]) == pytest.approx(0.45)      # seen twice: it counts
    assert clearance([a, b]) == pytest.approx(0.45)         # no majority: the cautious one
    assert clearance([]) == pytest.approx(1.0)              # no scan yet: the map walls


def test_fuse_scans_is_the_lower_median():
    fields = np.array([[[3.0]], [[1.0]], [[2.0]], [[5.0]]])
    assert fuse_scans(fields[:1])[0, 0] == 3.0
    assert fuse_scans(fields[:2])[0, 0] == 1.0
    assert fuse_scans(fields[:3])[0, 0] == 2.0
    assert fuse_scans(fields)[0, 0] == 2.0                  # of 1, 2, 3, 5: the lower median


@pytest.mark.parametrize("padding, passes", [(0.09, True), (0.10, False)])
def test_a_corridor_whose_centre_cells_are_exactly_at_the_padded_radius(padding, passes):
    # laser walls 8 cells (0.40 m) either side of the centre row y = 1.025: the centre cells
    # have clearance 0.40 m, their neighbours 0.35 m. Radius 0.3 m: the contact clearance is
    # 0.3 + 0.0707 + 0.02 = 0.391 m. With padding 0.09 (inscribed 0.39) that is the limit and
    # the centre row is admissible; with padding 0.10 the limit is 0.40 and `clearance <= 0.40`
    # closes the corridor: the robot never moves.
    costmap = CostmapConfig(robot_radius=0.3, footprint_padding=padding, inflation_radius=0.75)
    controller = DwaController(DwaConfig(max_vel_y=0.3), costmap)
    xs = np.arange(0.525, 3.6, 0.05)
    walls = np.vstack([np.column_stack((xs, np.full(len(xs), y))) for y in (0.625, 1.425)])
    controller.set_plan(np.column_stack((np.linspace(0.525, 3.025, 51), np.full(51, 1.025))))
    pose, trace = drive(controller, (0.525, 1.025, 0.0), (3.025, 1.025, 0.0), walls, steps=200)
    assert controller.at_goal_xy(pose, (3.025, 1.025, 0.0)) == passes
    if passes:
        local = LocalCostmap(ROOM.cells > 50, ROOM, pose, walls, 5.0)
        assert local.clearance(trace[:, 0], trace[:, 1]).min() == pytest.approx(0.40)
    else:
        assert np.hypot(*(trace[-1, :2] - trace[0, :2])) < 0.01
