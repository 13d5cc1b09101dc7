"""Doorways as walls (beyond the seed): openings narrower than `width` are cut at the opening.

Scans are ray-cast against wall segments here; expected ranges are the ranges to the wall line
through the door (front / cos a), not values from the module."""
import math

import numpy as np
import pytest

from semantic_nav.doorways import DoorConfig, close_doorways
from semantic_nav.laser_layer import model_from_scan

UTM = model_from_scan("utm", math.radians(-135), math.radians(0.25), 1081, 0.1, 30.0)
URG = model_from_scan("urg", math.radians(-120), math.radians(360 / 1024), 683, 0.02, 5.6)
DOORS = DoorConfig(width=1.4)


def cast(walls, laser=UTM):
    """Ranges of `laser` at the origin facing +x to the nearest of `walls` ((x0, y0, x1, y1)
    segments); beams that hit nothing read range_max (no return)."""
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    u = np.column_stack((np.cos(angles), np.sin(angles)))
    ranges = np.full(laser.beams, np.inf)
    for x0, y0, x1, y1 in walls:
        d = np.array([x1 - x0, y1 - y0])
        denominator = u[:, 0] * d[1] - u[:, 1] * d[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (x0 * d[1] - y0 * d[0]) / denominator
            s = (x0 * u[:, 1] - y0 * u[:, 0]) / denominator
        hit = np.isfinite(t) & (t > 0) & (s >= 0) & (s <= 1)
        ranges = np.where(hit, np.minimum(ranges, t), ranges)
    return np.where(ranges < laser.range_max, ranges, laser.range_max)


def corridor_end(door, front=2.0, half=1.0, office=6.0):
    """A corridor 2·half wide ending at x = front, a door (y0, y1) in that wall, an office wall
    at x = front + office (None: no office wall, the beams through the door see nothing)."""
    y0, y1 = door
    walls = [(-5, half, front, half), (-5, -half, front, -half),
             (front, -half, front, y0), (front, y1, front, half)]
    if office:
        walls.append((front + office, -10, front + office, 10))
    return walls


def beams_through(door, front=2.0, laser=UTM):
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    y = front * np.tan(angles)
    return (np.cos(angles) > 0) & (y > door[0]) & (y < door[1]), front / np.cos(angles)


@pytest.mark.parametrize("door", [(-0.5, 0.5), (0.0, 1.0), (-0.95, -0.1), (0.3, 0.9)])
@pytest.mark.parametrize("office", [6.0, None])
def test_a_door_straight_ahead_reads_as_the_wall(door, office):
    ranges = cast(corridor_end(door, office=office))
    closed = close_doorways(ranges, UTM, DOORS)
    through, wall = beams_through(door)
    assert through.sum() > 10 and np.all(ranges[through] > 3.0)
    # the beams next to the jambs may end on the jamb itself: all but the first and last
    inner = np.flatnonzero(through)[1:-1]
    np.testing.assert_allclose(closed[inner], wall[inner], atol=0.02)
    np.testing.assert_array_equal(closed[~through], ranges[~through])


def test_a_door_seen_by_the_urg_with_no_return_behind_it():
    ranges = cast(corridor_end((-0.5, 0.5), office=None), URG)
    closed = close_doorways(ranges, URG, DOORS)
    through, wall = beams_through((-0.5, 0.5), laser=URG)
    assert np.all(ranges[through] == URG.range_max)
    inner = np.flatnonzero(through)[1:-1]
    np.testing.assert_allclose(closed[inner], wall[inner], atol=0.02)


def test_an_opening_as_wide_as_a_corridor_is_kept():
    ranges = cast(corridor_end((-0.8, 0.8)))   # 1.6 m: wider than DOORS.width
    np.testing.assert_array_equal(close_doorways(ranges, UTM, DOORS), ranges)


def test_a_side_corridor_is_kept():
    # the left wall has a 1.8 m opening (x 1.0-2.8) into a side corridor going off to y = 8
    walls = [(-5, 1.0, 1.0, 1.0), (2.8, 1.0, 9.0, 1.0), (-5, -1.0, 9.0, -1.0),
             (1.0, 1.0, 1.0, 8.0), (2.8, 1.0, 2.8, 8.0), (1.0, 8.0, 2.8, 8.0)]
    ranges = cast(walls)
    np.testing.assert_array_equal(close_doorways(ranges, UTM, DOORS), ranges)


def test_a_door_beyond_max_range_and_width_zero_are_left_open():
    ranges = cast(corridor_end((-0.5, 0.5), front=6.0))
    far = close_doorways(ranges, UTM, DoorConfig(width=1.4, max_range=5.0))
    np.testing.assert_array_equal(far, ranges)
    assert close_doorways(ranges, UTM, DoorConfig(width=0.0)) is ranges


def test_the_input_is_not_changed():
    ranges = cast(corridor_end((-0.5, 0.5)))
    before = ranges.copy()
    close_doorways(ranges, UTM, DOORS)
    np.testing.assert_array_equal(ranges, before)
