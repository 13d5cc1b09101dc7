"""Ray casting against independent geometry: a wall at a known distance."""
import math

import numpy as np
import pytest
from sim2d_fixtures import LASER_DIR, room_grid

from sim2d.laser import LaserSensor, circle_ranges, find_laser_model, overlay_circles
from floorplan.occupancy_map import OCCUPIED, OccupancyMap
from sim2d.raycast import GridGeometry, RangeTable, RangeTableConfig, ray_march


@pytest.fixture(scope="module")
def geometry():
    return GridGeometry.from_map(room_grid())


@pytest.fixture(scope="module")
def table():
    """Table of a small room (6 m x 6 m, wall face at x = 5.0 m): quick to build."""
    cells = np.zeros((120, 120), dtype=np.int8)
    cells[:2, :] = cells[-2:, :] = cells[:, :2] = cells[:, 100:] = OCCUPIED
    small = GridGeometry.from_map(OccupancyMap(cells=cells, resolution=0.05))
    return RangeTable.build(small, RangeTableConfig(cell_size=0.1, angle_bins=1440,
                                                    min_clearance=1.0, max_range=30.0))


def test_beam_perpendicular_to_wall_returns_its_distance(geometry):
    # wall face at x = 5.0 m; from (1.23, 3.0) along +x the distance is 3.77 m
    assert ray_march(geometry, 1.23, 3.0, np.array([0.0]), 30.0)[0] == pytest.approx(3.77, abs=1e-9)


def test_oblique_beams_hit_the_wall_at_d_over_cos(geometry):
    angles = np.deg2rad([-40.0, -20.0, 10.0, 35.0])
    expected = 3.77 / np.cos(angles)          # all hit the face x = 5.0 below y = 8.0
    np.testing.assert_allclose(ray_march(geometry, 1.23, 4.0, angles, 30.0), expected, atol=1e-9)


def test_beam_through_the_gap_reaches_the_outer_wall(geometry):
    # above y = 8 m the inner wall is open: the beam ends on the east outer wall (x = 9.9 m)
    assert ray_march(geometry, 1.0, 9.0, np.array([0.0]), 30.0)[0] == pytest.approx(8.9, abs=1e-9)


def test_axis_beams_from_a_rounding_error_below_a_cell_boundary_hit_the_walls(geometry):
    # 8.6 / 0.05 = 171.99999999999997 cells: the start sits a rounding error below a boundary,
    # as the range table's sample points do; along the axes the walls are 1.9 m (x = 9.9),
    # 1.3 m (y = 9.9), 7.9 m (x = 0.1, above the inner wall's end) and 8.5 m (y = 0.1) away
    ranges = ray_march(geometry, 8.0, 8.6, np.array([0.0, 0.5, 1.0, -0.5]) * math.pi, 30.0)
    np.testing.assert_allclose(ranges, [1.9, 1.3, 7.9, 8.5], atol=1e-9)


def test_beam_beyond_max_range_returns_inf(geometry):
    assert np.isinf(ray_march(geometry, 1.23, 3.0, np.array([0.0]), 3.0)[0])


def test_table_matches_the_wall_distance_between_sample_points(table):
    bin_width = 2 * math.pi / 1440
    angles = np.array([0, 40, -80, 120]) * bin_width       # 0, 10, -20, 30 degrees
    ranges = table.cast(1.23, 3.01, angles)                # not on a sample point
    np.testing.assert_allclose(ranges, 3.77 / np.cos(angles), atol=1e-3)  # mm storage


def test_table_fan_equals_table_cast(table):
    bin_width = 2 * math.pi / 1440
    fan = table.cast_fan(2.37, 3.44, -540 * bin_width, 1081, 1)
    direct = table.cast(2.37, 3.44, (np.arange(1081) - 540) * bin_width)
    np.testing.assert_allclose(fan, direct)


def test_table_reads_a_direction_the_same_at_any_turn_of_the_circle(table):
    """Negative bins (within one turn) and angles several turns out (the modulo) read the bin
    of the direction in [0, 2 pi)."""
    rng = np.random.default_rng(7)
    base = rng.uniform(0.0, 2 * math.pi, 300)
    direct = table.cast(2.37, 3.44, base)
    for turns in (-1, 1, -3, 5):
        shifted = table.cast(2.37, 3.44, base + turns * 2 * math.pi)
        bins = np.rint((base + turns * 2 * math.pi) / table.bin_width).astype(int) % 1440
        same = bins == np.rint(base / table.bin_width).astype(int) % 1440   # no tie moved
        np.testing.assert_array_equal(shifted[same], direct[same])
        assert same.mean() > 0.95
    rows = table.cast_rows([2.37, 1.5], [3.44, 2.0], [-3.0, 3.1], base)
    for k, (x, y, yaw) in enumerate(((2.37, 3.44, -3.0), (1.5, 2.0, 3.1))):
        np.testing.assert_array_equal(rows[k], table.cast(x, y, base + yaw))


def test_table_refuses_points_it_does_not_cover(table):
    assert table.cast(4.5, 3.0, np.array([0.0])) is None     # 0.5 m from the wall


def test_utm30lx_scan_of_a_wall_is_within_its_noise(geometry):
    model = find_laser_model("utm_30lx", LASER_DIR)
    assert model.num_beams == 1081
    laser = LaserSensor(model, (0.0, 0.0, 0.0), geometry, seed=5)
    centre = 540                                   # beam straight ahead
    assert laser.angles[centre] == pytest.approx(0.0, abs=1e-9)
    # the 241 beams within +-30 deg of it end on the wall face x = 5.0 m at 3.77 m / cos
    beams = slice(centre - 120, centre + 121)
    expected = 3.77 / np.cos(laser.angles[beams])
    scans = np.array([laser.scan((1.23, 3.0, 0.0))[beams] - expected for _ in range(10)])
    scans[~np.isfinite(scans)] = np.nan             # dropouts return nothing
    errors = scans[np.isfinite(scans)]
    assert errors.size > 2300
    assert abs(errors.mean()) < 4 * model.noise_std / math.sqrt(errors.size)
    assert errors.std() == pytest.approx(model.noise_std, rel=0.1)
    # and each beam's noise changes from scan to scan (the mean per-beam sample std of 10 scans
    # is c4(10) = 0.973 times the noise's)
    per_beam = np.nanstd(scans, axis=0, ddof=1)
    assert np.nanmean(per_beam) == pytest.approx(0.973 * model.noise_std, rel=0.1)


def test_reseed_restarts_the_noise_whatever_came_before(geometry):
    model = find_laser_model("utm_30lx", LASER_DIR)
    laser = LaserSensor(model, (0.0, 0.0, 0.0), geometry, seed=5)
    pose = (1.23, 3.0, 0.0)
    laser.reseed(11)
    first = [laser.scan(pose) for _ in range(3)]
    for _ in range(7):                    # an earlier "episode" of a different length
        laser.scan(pose)
    laser.reseed(11)
    again = [laser.scan(pose) for _ in range(3)]
    assert all(np.array_equal(a, b) for a, b in zip(first, again))
    laser.reseed(12)
    assert not np.array_equal(laser.scan(pose), first[0])


def test_circle_ranges_hits_the_near_side_of_a_person():
    r = circle_ranges(0.0, 0.0, np.array([0.0, math.pi / 2]), [(2.0, 0.0, 0.2)])
    assert r[0] == pytest.approx(1.8)
    assert np.isinf(r[1])


@pytest.mark.parametrize("fan", [(-2.356, 0.004363, 1081),          # UTM-30LX, 270 degrees
                                 (-math.pi, 2 * math.pi / 360, 360)])   # a full circle
def test_windowed_circles_hit_what_every_beam_against_every_circle_hits(fan):
    """overlay_circles casts each circle only on its angular window; circle_ranges casts every
    circle on every beam. Random crowds around a laser at random headings, seam included."""
    angle_min, increment, beams = fan
    local = angle_min + np.arange(beams) * increment
    rng = np.random.default_rng(4)
    for _ in range(200):
        lx, ly, lyaw = rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-4, 4)
        circles = np.column_stack([lx + rng.uniform(-8, 8, 25), ly + rng.uniform(-8, 8, 25),
                                   rng.uniform(0.05, 1.0, 25)])
        circles[0, :2] = lx + 0.1, ly             # the laser inside a circle: unseen, as before
        circles[1, :2] = lx - 2.0, ly + 1e-3      # straddling the fan's +-pi seam (yaw 0)
        base = rng.uniform(0.5, 30.0, beams)
        windowed = overlay_circles(base, lx, ly, lyaw, circles, np.cos(local), np.sin(local),
                                   angle_min, increment)
        every = np.minimum(base, circle_ranges(lx, ly, local + lyaw, circles))
        np.testing.assert_allclose(windowed, every, rtol=0, atol=1e-9)


def test_segments_clear_only_where_no_wall_is_crossed(geometry):
    from sim2d.raycast import segments_clear
    # the inner wall spans x in [5.0, 5.2] below y = 8 m
    clear = segments_clear(geometry, 2.0, 3.0, [(4.5, 3.0), (7.0, 3.0), (7.0, 9.0), (2.0, 7.9)])
    assert clear.tolist() == [True, False, False, True]  # (7, 9): crosses x = 5 at y = 6.6
    assert segments_clear(geometry, 2.0, 9.0, [(7.0, 9.0)]).tolist() == [True]   # above it


def test_urg04lx_range_proportional_noise_keeps_no_return_as_inf(geometry):
    model = find_laser_model("urg_04lx", LASER_DIR)
    assert model.num_beams == 683
    laser = LaserSensor(model, (0.0, 0.0, 0.0), geometry, seed=2)
    ranges = laser.scan((1.0, 9.0, 0.0))            # 8.9 m to the east wall: beyond 5.6 m
    assert not np.isnan(ranges).any()
    assert np.isinf(ranges[341])                     # centre beam


def test_laser_falls_back_to_exact_marching_where_the_table_has_no_entry(table):
    model = find_laser_model("utm_30lx", LASER_DIR)
    laser = LaserSensor(model, (0.0, 0.0, 0.0), table.geometry, table, seed=1)
    near_wall = (4.5, 3.0, 0.0)                     # 0.5 m from the wall: not tabulated
    assert table.cast(4.5, 3.0, np.array([0.0])) is None
    assert laser.true_ranges(near_wall)[540] == pytest.approx(0.5, abs=1e-9)
    tabulated = (1.23, 3.01, 0.0)
    assert laser.true_ranges(tabulated)[540] == pytest.approx(3.77, abs=1e-3)
