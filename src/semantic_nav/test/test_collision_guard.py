"""Collision guard (beyond the seed): v limited along the commanded arc, ω kept unless the
guard steers round a blocked arc.

Expected values come from the closed-form clearance to straight walls, not from the guard."""
import math

import numpy as np
import pytest

from semantic_nav.collision_guard import (GuardConfig, arc_positions, format_guard_actions,
                                          guard_velocity, ramped_arc_positions, scan_points,
                                          steer_around)
from semantic_nav.laser_layer import model_from_scan

UTM = model_from_scan("utm", math.radians(-135), math.radians(0.25), 1081, 0.1, 30.0)
REACH = 0.35     # default radius + margin


def wall_scan(front=None, left=None, right=None, laser=UTM):
    """Ranges of `laser` at the origin facing +x between walls x = front, y = left, y = -right."""
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    ranges = np.full(laser.beams, np.inf)
    with np.errstate(divide="ignore"):
        if front is not None:
            ranges = np.where(np.cos(angles) > 1e-9, np.minimum(ranges, front / np.cos(angles)),
                              ranges)
        if left is not None:
            ranges = np.where(np.sin(angles) > 1e-9, np.minimum(ranges, left / np.sin(angles)),
                              ranges)
        if right is not None:
            ranges = np.where(np.sin(angles) < -1e-9,
                              np.minimum(ranges, -right / np.sin(angles)), ranges)
    return np.where(ranges < laser.range_max, ranges, laser.range_max)


def points(**walls):
    return scan_points(wall_scan(**walls), UTM)


def expected_straight(v, front, config=GuardConfig()):
    """Last checked pose (every v·resolution) whose gap to the wall x = front is >= REACH."""
    step = abs(v) * config.resolution
    last_safe = math.floor(round((front - REACH) / step, 9)) * step
    return min(v, last_safe / config.horizon)


def test_scan_points_drop_invalid_and_no_return_readings():
    ranges = np.array([1.0, np.nan, 0.05, 30.0, 2.0])
    laser = model_from_scan("five", -math.pi / 2, math.pi / 4, 5, 0.1, 30.0)
    got = scan_points(ranges, laser, laser_x=0.1)
    np.testing.assert_allclose(got, [[0.1, -1.0], [0.1 + 2.0 * math.cos(math.pi / 2), 2.0]],
                               atol=1e-12)


def test_arc_positions_straight_and_turning():
    np.testing.assert_allclose(arc_positions(0.4, 0.0, [0.0, 1.0]), [[0, 0], [0.4, 0]])
    quarter = arc_positions(0.5, math.pi / 2, [1.0])[0]      # radius 1/π, a quarter circle
    np.testing.assert_allclose(quarter, [1 / math.pi, 1 / math.pi], atol=1e-12)


def test_open_corridor_passes_unchanged():
    assert guard_velocity(0.4, 0.0, points(left=1.0, right=1.0)) == 0.4
    assert guard_velocity(0.4, 0.0, points(front=2.0, left=0.5, right=0.5)) == 0.4
    assert guard_velocity(0.4, 0.0, points(front=0.76)) == 0.4    # beyond v·horizon + REACH


@pytest.mark.parametrize("front", [0.4, 0.6, 0.7, 0.74])
def test_wall_ahead_slows_to_the_free_path(front):
    got = guard_velocity(0.4, 0.0, points(front=front))
    assert got == pytest.approx(expected_straight(0.4, front), abs=1e-9)
    assert got < 0.4


def test_turn_into_a_side_wall_is_slowed_but_omega_untouched():
    # arc y(t) = v/ω (1 - cos ωt) toward the wall y = 0.5: blocked once 0.5 - y < REACH
    v, w = 0.4, 1.0
    t_block = math.acos(1 - (0.5 - REACH) * w / v)
    last_safe = math.floor(t_block / 0.05) * 0.05
    assert guard_velocity(v, w, points(left=0.5, right=2.0)) == pytest.approx(v * last_safe)
    assert guard_velocity(v, -w, points(left=0.5, right=2.0)) == v      # turning away: free


def test_inside_the_margin_only_moves_that_open_the_gap():
    near = points(front=0.32)
    reversing = GuardConfig(allow_reverse=True)
    assert guard_velocity(0.3, 0.0, near, reversing) == 0.0
    assert guard_velocity(-0.1, 0.0, near, reversing) == -0.1     # backing off opens the gap
    beside = points(left=0.33, right=2.0)
    assert guard_velocity(0.1, 0.0, beside) == 0.1            # along the wall: no closer
    assert guard_velocity(0.1, -0.5, beside) == 0.1           # away from it
    assert guard_velocity(0.1, 0.5, beside) == 0.0            # toward it


def test_reversing_into_the_blind_rear_is_blocked_by_default():
    assert guard_velocity(-0.1, 0.8, points(left=2.0, right=2.0)) == 0.0
    assert guard_velocity(-0.1, 0.0, np.zeros((0, 2))) == 0.0
    assert guard_velocity(-0.1, 0.0, points(front=2.0), GuardConfig(allow_reverse=True)) == -0.1


def test_disabled_guard_and_no_returns_pass_everything():
    assert guard_velocity(0.4, 0.0, points(front=0.4), GuardConfig(enabled=False)) == 0.4
    assert guard_velocity(0.4, 0.0, np.zeros((0, 2))) == 0.4
    assert guard_velocity(0.0, 1.0, points(front=0.31)) == 0.0


V_MOVE = 0.02    # postprocess.v_move: the slowest real motion


def test_steering_takes_the_nearest_omega_that_no_longer_closes_on_the_wall():
    """Inside the margin of the wall y = 0.33 every ω > 0 closes on it; ω = 0 runs along it, so
    on the 0.1 rad/s grid the nearest usable ω to 0.5 is 0.0, at the full 0.1 m/s."""
    beside = points(left=0.33, right=2.0)
    assert steer_around(0.1, 0.5, beside, V_MOVE) == (0.1, 0.0)
    assert steer_around(0.1, 0.5, beside, V_MOVE, GuardConfig(steer=False)) == (0.0, 0.5)


def test_a_free_or_slowed_arc_and_a_stop_are_not_steered():
    assert steer_around(0.4, 0.3, points(left=1.0, right=1.0), V_MOVE) == (0.4, 0.3)
    slowed = steer_around(0.4, 0.0, points(front=0.6), V_MOVE)
    assert slowed == (pytest.approx(expected_straight(0.4, 0.6)), 0.0)
    assert steer_around(0.01, 0.2, points(front=0.3), V_MOVE) == (0.0, 0.2)    # below v_move


def test_with_every_arc_blocked_the_robot_turns_in_place():
    """A wall 0.36 m ahead: the first checked pose (0.3 m/s · 0.05 s = 0.015 m on) is inside
    the 0.35 m reach on every arc, so no arc is usable and v' = 0."""
    wall = points(front=0.36)
    assert steer_around(0.3, 0.2, wall, V_MOVE) == (0.0, 0.5)      # the network's side
    assert steer_around(0.3, -0.8, wall, V_MOVE) == (0.0, -0.8)    # already turning fast
    corner = np.array([[0.36, -0.05], [0.36, -0.5], [0.36, -1.0]])   # returns ahead-right
    assert steer_around(0.3, 0.0, corner, V_MOVE) == (0.0, 0.5)    # away from the nearest
    assert steer_around(0.3, 0.0, corner * [1, -1], V_MOVE) == (0.0, -0.5)


def test_ramped_path_follows_the_omega_ramp():
    """ω from 0 to 1 rad/s at 2 rad/s²: θ(t) = t² up to 0.5 s, then 0.25 + (t - 0.5); the end
    point at 1 s against a fine trapezoid integration of that heading."""
    times = np.linspace(0.0, 1.0, 21)
    got = ramped_arc_positions(0.4, 1.0, 0.0, 2.0, times)[-1]
    t = np.linspace(0.0, 1.0, 100001)
    theta = np.where(t <= 0.5, t ** 2, 0.25 + (t - 0.5))
    expected = [np.trapz(0.4 * np.cos(theta), t), np.trapz(0.4 * np.sin(theta), t)]
    np.testing.assert_allclose(got, expected, atol=1e-4)
    instant = ramped_arc_positions(0.5, math.pi / 2, 0.0, 1e9, times)
    np.testing.assert_allclose(instant, arc_positions(0.5, math.pi / 2, times), atol=1e-3)


def test_guard_checks_the_path_the_base_drives_while_omega_changes():
    """Turning right away from a wall 0.45 m to the left is free on the commanded arc. A base
    still turning left at 1 rad/s that changes ω at 1 rad/s² first swings towards the wall: its
    heading peaks at 0.5 rad after 1 s, about 0.12 m nearer the wall, inside the 0.35 m reach."""
    wall = points(left=0.45, right=2.0)
    slow = GuardConfig(angular_accel=1.0)
    assert guard_velocity(0.4, -1.0, wall, slow) == 0.4
    assert guard_velocity(0.4, -1.0, wall, slow, w_now=-1.0) == 0.4
    assert guard_velocity(0.4, -1.0, wall, slow, w_now=1.0) < 0.4
    assert guard_velocity(0.4, -1.0, wall, GuardConfig(angular_accel=0.0), w_now=1.0) == 0.4


def test_guard_actions_format_for_the_diagnostics():
    counts = {"turned": 3, "slowed": 1, "steered": 2}
    assert format_guard_actions(counts) == "slowed 1, held 0, steered 2, turned 3"
