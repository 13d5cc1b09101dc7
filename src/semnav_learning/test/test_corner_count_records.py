"""Corner counts in training data (corner_count on records): the counts of a demonstration
against the oracle's corners, and the side ranges and doorway-closed scans of record files."""
import math

import numpy as np
import pytest

from semantic_nav.corner_count import CornerCountConfig, count_inputs, side_ranges
from semnav_learning.demonstrations import demonstrate, world_for_floor
from semnav_learning.route_oracle import RouteOracle
from semnav_learning.training import TrainingConfig, decision_step
from floorplan.occupancy_map import load_map
from tamp_resources import resource

ROOT = resource()


def _travel(commands, rate):
    """Distance [m] driven before each step."""
    return np.concatenate([[0.0], np.cumsum(np.abs(commands[:, 0]) / rate)[:-1]])


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
    from semnav_learning.training import load_episodes
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
    from semnav_learning.training import load_episodes
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
