"""Collision guard (beyond the seed): v limited along the commanded arc, ω never changed.

Expected values come from the closed-form clearance to straight walls, not from the guard."""
import math

import numpy as np
import pytest

from semantic_nav.collision_guard import (GuardConfig, arc_positions, guard_velocity,
                                          scan_points)
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
