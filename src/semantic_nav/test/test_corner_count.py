"""Corners counted so far from the side beams (corner_count): the network's count input."""
import math
from pathlib import Path

import numpy as np
import pytest

from semantic_nav.corner_count import (CornerCountConfig, CornerCounter, count_inputs,
                                       one_hot_counts, side_ranges)
from semantic_nav.demonstrations import demonstrate, world_for_floor
from semantic_nav.route_oracle import RouteOracle
from semantic_nav.training import TrainingConfig, decision_step
from floorplan.occupancy_map import load_map

ROOT = Path(__file__).resolve().parents[3]


def test_side_ranges_take_the_shortest_beam_round_each_side():
    # 9 beams every 45° from -180°: +90° is beam 6, -90° is beam 2
    ranges = np.full((1, 9), 5.0)
    ranges[0, 6], ranges[0, 2] = 1.5, 2.0
    sides = side_ranges(ranges, -math.pi, math.pi / 4, 5.0)
    assert sides.tolist() == [[1.5, 2.0]]
    with pytest.raises(ValueError, match="no beam within 5.0° of"):
        side_ranges(np.ones((1, 2)), 0.0, 0.1, 5.0)      # 0° … 5.7°: no side beam


def _travel(commands, rate):
    """Distance [m] driven before each step."""
    return np.concatenate([[0.0], np.cumsum(np.abs(commands[:, 0]) / rate)[:-1]])


def _corridor(openings, length=20.0, speed=0.5, rate=10.0):
    """A drive at `speed` along a corridor with walls 1 m to each side; `openings`: (side
    column, from [m], to [m]) where that side reads 4 m."""
    commands = np.tile([speed, 0.0], (int(length / speed * rate), 1)).astype(np.float32)
    s = _travel(commands, rate)
    sides = np.ones((len(commands), 2), np.float32)
    for column, first, last in openings:
        sides[(s >= first) & (s <= last), column] = 4.0
    return sides, commands


def test_each_corner_counts_once_it_is_min_width_long_doors_never():
    """Left branch 3-5 m, a 0.8 m door on the right at 7 m, a crossroad 10-12 m (its right side
    opens a little later: the same corner), a right branch 15-17 m: the count rises 1 m
    (min_width) into each corner, within a step of 5 cm."""
    sides, commands = _corridor([(0, 3.0, 5.0), (1, 7.0, 7.8), (0, 10.0, 12.0),
                                 (1, 10.5, 12.5), (1, 15.0, 17.0)])
    counts = count_inputs(sides, commands, 10.0, CornerCountConfig())
    s = _travel(commands, 10.0)
    rises = s[np.flatnonzero(np.diff(counts)) + 1]
    assert counts[0] == 0 and np.all(np.diff(counts) >= 0) and counts[-1] == 3
    assert rises == pytest.approx([4.0, 11.0, 16.0], abs=0.11)


def test_counts_saturate_at_max_count():
    sides, commands = _corridor([(0, 2.0, 3.5), (1, 5.0, 6.5), (0, 8.0, 9.5), (1, 11.0, 12.5),
                                 (0, 14.0, 15.5)])
    counts = count_inputs(sides, commands, 10.0, CornerCountConfig(max_count=3))
    assert counts.max() == 3 and sorted(set(counts.tolist())) == [0, 1, 2, 3]


def test_online_counter_joins_the_other_side_of_a_crossroad_and_resets():
    counter = CornerCounter(CornerCountConfig(min_width=1.0))
    seen = []
    for step in range(80):               # 0.1 m per step: left open 1-4 m, right open 3-6 m
        sides = (4.0 if 10 <= step < 40 else 1.0, 4.0 if 30 <= step < 60 else 1.0)
        seen.append(counter.observe(sides))
        counter.advance(-0.1)            # reversing drives as far
    assert seen[19] == 0 and seen[20] == 1 and seen[-1] == 1
    counter.reset()
    assert counter.observe((1.0, 1.0)) == 0 and counter.travel == 0.0


def test_one_hot_counts():
    assert one_hot_counts([0, 3, 1], 3).tolist() == [[1, 0, 0, 0], [0, 0, 0, 1], [0, 1, 0, 0]]


def test_counts_from_a_demonstration_match_the_oracles_corners():
    """Independent check on office_comb's spine, heading north from the south end, where the
    oracle finds branches west at y = 10, east at 14 and a crossroad at 18: the expert's drive to
    the 3rd corner on the right (class 8, the crossroad) has counted two corners when it turns,
    each 1 m (min_width) past where the oracle's walk puts the corner's first branch."""
    map_path = ROOT / "maps" / "office_comb.yaml"
    oracle = RouteOracle(load_map(map_path))
    world = world_for_floor(ROOT / "config" / "worlds" / "office_penguin.yaml", map_path,
                            cache_dir=None, raycast="march")
    start = (18.0, 5.0, math.pi / 2)
    demo = demonstrate(world, "penguin", oracle, start, 8, record_rate=10.0)
    assert demo.ok, demo
    samples = demo.sequence.samples
    commands = np.array([[s.v, s.omega] for s in samples], np.float32)
    laser = world.robot("penguin").lasers[0].model
    sides = side_ranges(np.array([s.ranges for s in samples]), laser.angle_min,
                        laser.angle_increment, CornerCountConfig().window_deg)
    counts = count_inputs(sides, commands, 10.0, CornerCountConfig())
    decision = decision_step(commands, 10.0, TrainingConfig())
    assert counts[decision] == 2
    s = _travel(commands, 10.0)
    rises = s[np.flatnonzero(np.diff(counts[:decision])) + 1]
    walk = oracle.walk(start)
    expected = [min(b.start for b in corner.branches.values()) + 1.0
                for corner in walk.corners[:2]]
    assert rises == pytest.approx(expected, abs=0.5)


def test_record_files_bring_their_side_ranges_and_a_broken_cache_is_rebuilt(tmp_path):
    from penguin_base.record_format import RecordSequence, Sample, format_records
    from semantic_nav.laser_layer import load_laser_config
    from semantic_nav.training import load_episodes
    models, canonical, preprocess = load_laser_config(ROOT / "config" / "semnav_laser.yaml")
    laser = models["utm30lx"]            # beam 900 is +90°, beam 180 is -90°
    ranges = np.full(laser.beams, 1.0)
    ranges[900], ranges[180] = 0.8, 0.9
    samples = [Sample(0.3, 0.0, tuple(ranges)), Sample(0.3, 0.1, tuple(np.full(laser.beams, 3.0)))]
    path = tmp_path / "floor.records"
    path.write_text(format_records([RecordSequence(5, samples)]))
    cache = tmp_path / "cache"

    def load():
        return load_episodes([path], laser, canonical, preprocess, cache, rate=10.0)

    first = load()[0]
    assert first.label == 5
    np.testing.assert_allclose(first.sides, [[0.8, 0.9], [3.0, 3.0]], rtol=1e-6)
    [cached] = cache.glob("*.npz")
    cached.write_bytes(cached.read_bytes()[:100])         # a write cut short
    again = load()[0]
    np.testing.assert_array_equal(again.sides, first.sides)
    np.testing.assert_array_equal(again.scans, first.scans)
    assert [p.name for p in cache.glob("*.npz")] == [cached.name]   # rebuilt in place


def test_record_scans_can_have_their_doorways_closed_in_a_cache_of_their_own(tmp_path):
    """train_semnav --door-width: the network trains on the scans the follower sees."""
    from penguin_base.record_format import RecordSequence, Sample, format_records
    from semantic_nav.doorways import DoorConfig
    from semantic_nav.laser_layer import load_laser_config, preprocess_scan
    from semantic_nav.training import load_episodes
    models, canonical, preprocess = load_laser_config(ROOT / "config" / "semnav_laser.yaml")
    laser = models["utm30lx"]            # beam 540 is straight ahead
    angles = laser.angle_min + laser.angle_increment * np.arange(laser.beams)
    with np.errstate(divide="ignore"):
        wall = np.where(np.cos(angles) > 1e-9, 2.0 / np.cos(angles), 30.0)
    wall = np.minimum(wall, 30.0)
    door = wall.copy()
    door[np.abs(2.0 * np.tan(angles)) < 0.5] = 30.0      # a 1 m door 2 m ahead, no return
    door[np.cos(angles) <= 1e-9] = 30.0
    path = tmp_path / "floor.records"
    path.write_text(format_records([RecordSequence(1, [Sample(0.3, 0.0, tuple(door))])]))
    cache = tmp_path / "cache"
    raw = load_episodes([path], laser, canonical, preprocess, cache, rate=10.0)[0]
    closed = load_episodes([path], laser, canonical, preprocess, cache, rate=10.0,
                           doors=DoorConfig(width=1.4))[0]
    plain = preprocess_scan(wall, laser, canonical, preprocess)[0]
    assert len(list(cache.glob("*.npz"))) == 2
    assert np.abs(raw.scans[0] - plain).max() > 0.1 * plain.max()
    np.testing.assert_allclose(closed.scans[0], plain, atol=0.01 * plain.max())
