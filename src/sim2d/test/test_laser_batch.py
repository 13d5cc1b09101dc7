"""Lasers of one model cast together (laser_batch) give the scans each laser gives alone."""
import math

import numpy as np
import pytest
import yaml
from sim2d_fixtures import LASER_DIR

from sim2d.laser_batch import batch_key
from sim2d.world import World
from sim2d.world_config import load_world_config

POSES = ([2.0, 3.0, 0.0], [3.0, 8.8, -2.5], [7.5, 3.0, 2.0], [8.0, 8.6, math.pi])
TURNS = (0.4, -0.7, 1.1, -0.2)    # each robot drives a circle [rad/s] at 0.3 m/s
SECONDS = 1.0                     # driven: 40 UTM-30LX or 10 URG-04LX scans per robot


def crowd(tmp_path, room_map, model, batch):
    """Four robots with one laser model, two walking people and a door closed at 0.5 s."""
    data = {
        "map": str(room_map),
        "doors": [{"name": "east", "box": [5.0, 8.0, 5.2, 9.9]}],
        "robots": [{"name": f"r{k}", "drive": "differential", "radius": 0.25, "pose": pose,
                    "namespace": f"r{k}",
                    "lasers": [{"model": model, "raycast": "table", "seed": k}]}
                   for k, pose in enumerate(POSES)],
        "people": [{"name": name, "shirt_colour": [200, 40, 40], "pose": start,
                    "posture": "standing", "activity": "walk",
                    "schedule": [{"time": 0.2, "pose": end, "posture": "standing",
                                  "activity": "walk"}]}
                   for name, start, end in (("Ann", [4.0, 5.0, 0.0], [1.0, 6.0, 0.0]),
                                            ("Ben", [7.0, 6.0, 0.0], [6.0, 1.0, 0.0]))]}
    path = tmp_path / f"{model}.yaml"
    path.write_text(yaml.safe_dump(data))
    world = World(load_world_config(path, LASER_DIR), cache_dir=None)   # lazy_tables: shared
    world.batch_scans = batch
    return world


@pytest.mark.parametrize("model, fan", [("utm_30lx", True), ("urg_04lx", False)])
def test_lasers_cast_together_give_each_lasers_own_scans(tmp_path, room_map, model, fan,
                                                         lazy_tables):
    together, alone = (crowd(tmp_path, room_map, model, batch) for batch in (True, False))
    lasers = [robot.lasers[0] for robot in together.robots]
    assert len({batch_key(laser) for laser in lasers}) == 1          # one batch
    assert bool(lasers[0].fan_step) == fan                         # both table paths
    steps = round(SECONDS / lasers[0].model.scan_time)
    scans, hits = 0, 0
    for step in range(steps):
        if step == 5:
            for world in (together, alone):
                world.set_door("east", True)
        for world in (together, alone):
            for robot, turn in zip(world.robots, TURNS):
                world.set_twist(robot.name, 0.3, 0.0, turn)
            world.step(lasers[0].model.scan_time)
        for mine, theirs in zip(together.robots, alone.robots):
            assert mine.state.pose == theirs.state.pose
            assert np.array_equal(mine.scans[0].ranges, theirs.scans[0].ranges)
            assert mine.scans[0].ranges.dtype == np.float32
            scans += 1
        # the other robots and the people show in the scans: some beams end on a circle
        circles = np.array(together._obstacle_circles(None))
        for robot in together.robots:
            laser = robot.lasers[0]
            x, y, yaw = laser.pose_in_map(robot.state.pose)
            ranges = robot.scans[0].ranges
            ends = np.stack([x + ranges * np.cos(yaw + laser.angles),
                             y + ranges * np.sin(yaw + laser.angles)], axis=1)
            finite = np.isfinite(ranges)
            gaps = np.hypot(ends[finite, None, 0] - circles[None, :, 0],
                            ends[finite, None, 1] - circles[None, :, 1]) - circles[None, :, 2]
            hits += int((np.abs(gaps) < 0.1).any(axis=1).sum())
    assert scans == 4 * steps >= 40 and hits > 100
