import math

import numpy as np
import pytest
from helpers import open_room

from nav_mocks.clearance import ContactClearance
from nav_mocks.costmap import Costmap, CostmapConfig, contact_clearance
from nav_mocks.dwa import (DwaConfig, DwaController, local_plan, rollout, sample_velocities,
                           velocity_window)

COSTMAP = CostmapConfig(robot_radius=0.2, footprint_padding=0.1, inflation_radius=0.5)
ROOM = open_room(80, 60, resolution=0.05)          # 4 m x 3 m
ROOM_COSTMAP = Costmap(ROOM, COSTMAP)


def room_clearance(points, subdivision=10):
    """The DWA's clearance in ROOM: its walls' contact region plus `points` as laser hits."""
    return ContactClearance(ROOM_COSTMAP.contact_depth(subdivision), subdivision, ROOM,
                            COSTMAP.robot_radius, points)


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
        local = room_clearance(points)
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
    # plan, closer than radius + contact_margin (0.22 m), so the robot must swerve to pass it
    box = np.array([(2.0 + dx, 1.85 + dy) for dx in np.linspace(-0.15, 0.15, 7)
                    for dy in np.linspace(-0.15, 0.15, 7)])
    pose, trace = drive(controller, (0.5, 1.5, 0.0), (3.5, 1.5, 0.0), box, steps=200)
    assert controller.at_goal_xy(pose, (3.5, 1.5, 0.0))
    gaps = np.hypot(trace[:, None, 0] - box[None, :, 0], trace[:, None, 1] - box[None, :, 1])
    # the hits' clearance is Euclidean: the robot keeps radius + contact_margin = 0.22 m
    assert gaps.min() > COSTMAP.robot_radius + controller.config.contact_margin
    assert trace[:, 1].min() < 1.5 - 0.02          # it swerved away from the box


def test_boxed_in_robot_can_only_turn_in_place():
    # a ring of hits 0.23 m round the robot: 1 cm beyond radius + margin (0.22 m), so every
    # translation of the 1.5 s rollout reaches the limit; 0.15 m: already inside it, and every
    # translation comes closer to some hit
    controller = DwaController(DwaConfig(), COSTMAP)
    controller.set_plan(np.array([[1.0, 1.0], [2.0, 1.0]]))
    ring = np.array([(1.0 + 0.23 * math.cos(a), 1.0 + 0.23 * math.sin(a))
                     for a in np.linspace(0, 2 * math.pi, 60)])
    cmd = controller.best_command((1.0, 1.0, 0.0), (0.0, 0.0, 0.0), room_clearance(ring))
    assert cmd[0] == 0.0 and cmd[1] == 0.0
    ring = np.array([(1.0 + 0.15 * math.cos(a), 1.0 + 0.15 * math.sin(a))
                     for a in np.linspace(0, 2 * math.pi, 60)])
    cmd = controller.best_command((1.0, 1.0, 0.0), (0.0, 0.0, 0.0), room_clearance(ring))
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


def test_keeps_radius_plus_margin_from_a_wall_only_the_laser_sees():
    # radius 0.2 m, contact_margin 0.02 m: the DWA's limit for laser hits is 0.22 m (Euclidean).
    # The plan runs 0.20 m from a wall only the laser sees: the robot must leave the plan and
    # keep more than 0.22 m from every hit on every cycle.
    controller = DwaController(DwaConfig(contact_margin=0.02), COSTMAP)
    controller.set_plan(np.column_stack((np.linspace(0.5, 3.5, 61), np.full(61, 1.5))))
    wall = np.column_stack((np.linspace(1.5, 2.5, 41), np.full(41, 1.70)))
    assert controller.collision_radius(room_clearance(wall)) == pytest.approx(0.22)
    pose, trace = drive(controller, (0.5, 1.5, 0.0), (3.5, 1.5, 0.0), wall, steps=200)
    assert controller.at_goal_xy(pose, (3.5, 1.5, 0.0))
    gaps = np.hypot(trace[:, None, 0] - wall[None, :, 0], trace[:, None, 1] - wall[None, :, 1])
    assert gaps.min() > 0.22
