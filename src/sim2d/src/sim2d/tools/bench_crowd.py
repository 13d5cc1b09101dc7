"""Crowded worlds for scripts/bench_sim --crowd: several Penguins and walking people on one floor.

Robots: copies of the floor world's first robot (the Penguin with a UTM-30LX, 1081 beams at
40 Hz, range table), each steered toward open space by bench_sim.steer. People walk back
and forth between two free points in line of sight of each other. Every scan overlays the other
robots and the people; `windowed=False` casts each of them on every beam instead (the
reference), so both run on the same world and poses.
"""
import copy
import math
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

from sim2d.raycast import segments_clear
from sim2d.world import World

FREE_CLEARANCE = 0.8    # [m] robots and people start at least this far from walls
WALK_PERIOD = 20.0      # [s] a person turns back this often


def free_points(world, count, rng, taken=()):
    """`count` random points [(x, y)] of the floor with FREE_CLEARANCE to walls and 1.5 m to
    each other and to `taken`."""
    grid = world.grid
    x0, y0 = grid.origin[0], grid.origin[1]
    x1, y1 = x0 + grid.width * grid.resolution, y0 + grid.height * grid.resolution
    points = list(taken)
    for _ in range(200_000):
        if len(points) == len(taken) + count:
            return points[len(taken):]
        x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
        if world.geometry.clearance(x, y) < FREE_CLEARANCE:
            continue
        if all(math.hypot(x - px, y - py) > 1.5 for px, py in points):
            points.append((x, y))
    raise RuntimeError(f"no room for {count} more points on {world.config.map_path}")


def walk_partner(world, start, rng):
    """A free point 3-12 m from `start` in its line of sight (else `start`: the person stands)."""
    for _ in range(500):
        heading, distance = rng.uniform(-math.pi, math.pi), rng.uniform(3.0, 12.0)
        x, y = start[0] + distance * math.cos(heading), start[1] + distance * math.sin(heading)
        if world.geometry.clearance(x, y) < FREE_CLEARANCE:
            continue
        if segments_clear(world.geometry, start[0], start[1], [(x, y)])[0]:
            return x, y
    return start


def crowd_world_data(template, robots, people, seconds, seed=0):
    """World YAML data: `robots` copies of `template`'s first robot and `people` walkers, at
    random free poses (seeded)."""
    base = World.from_file(str(template))
    data = yaml.safe_load(Path(template).read_text())
    data["map"] = str(base.config.map_path)
    data.pop("graph", None)
    rng = np.random.default_rng(seed)
    starts = free_points(base, robots + people, rng)
    robot = data["robots"][0]
    data["robots"] = []
    for i, (x, y) in enumerate(starts[:robots]):
        entry = copy.deepcopy(robot)
        entry.update(name=f"penguin{i + 1}", namespace=f"penguin{i + 1}",
                     pose=[float(x), float(y), float(rng.uniform(-math.pi, math.pi))])
        for laser in entry["lasers"]:
            laser["frame"] = f"penguin{i + 1}/base_laser"
        data["robots"].append(entry)
    data["people"] = []
    for i, start in enumerate(starts[robots:]):
        other = walk_partner(base, start, rng)
        schedule = [{"time": float(t), "pose": [*map(float, (other if k % 2 == 0 else start)), 0.0]}
                    for k, t in enumerate(np.arange(1.0, seconds + 1.0, WALK_PERIOD))]
        data["people"].append({
            "name": f"person{i + 1}", "pose": [float(start[0]), float(start[1]), 0.0],
            "shirt_colour": {"joint1": [200, 40, 40], "joint2": [190, 35, 35],
                             "joint5": [195, 38, 38]},
            "schedule": schedule})
    return data


def world_from_data(template, data):
    """A World of crowd_world_data `data`, with the laser models of tamp_resources (as
    World.from_file's default)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "crowd.yaml"
        path.write_text(yaml.safe_dump(data))
        return World.from_file(str(path))


def crowd_world(template, robots, people, seconds, seed=0):
    return world_from_data(template, crowd_world_data(template, robots, people, seconds, seed))


def run_crowd(world, seconds, steer, windowed=True, batch=True):
    """Real-time factor of `world.step` (the robots' controller `steer` not counted) at the
    lasers' scan period for `seconds` of sim time, the lasers cast together (`batch`) or one by
    one; (factor, scans)."""
    dt = world.robots[0].lasers[0].model.scan_time
    world.batch_scans = batch
    for robot in world.robots:
        for laser in robot.lasers:
            laser.windowed = windowed
    wall = 0.0
    for _ in range(int(round(seconds / dt))):
        began = time.perf_counter()
        world.step(dt)
        wall += time.perf_counter() - began
        for robot in world.robots:
            v, w = steer(robot.scans[0].ranges, robot.lasers[0].angles)
            world.set_twist(robot.name, v, 0.0, w)
    return world.time / wall, sum(r.scans[0].count for r in world.robots)


CROWD_RUNS = (("windowed", True, True),       # the lasers of one model cast together
              ("one_by_one", True, False),    # each laser alone, windowed overlay
              ("every_beam", False, False))   # each laser alone, every beam x every circle


def bench_crowds(template, steer, seconds, robot_counts=(1, 4, 8), people_counts=(0, 10, 20)):
    """[{robots, people, windowed, one_by_one, every_beam, scans}]: real-time factors of each
    crowd with the windowed overlay, the lasers cast together (laser_batch) and one by one, and
    with every beam against every circle, on the same world and poses."""
    rows = []
    for robots in robot_counts:
        for people in people_counts:
            row = {"robots": robots, "people": people}
            data = crowd_world_data(template, robots, people, seconds)
            for name, windowed, batch in CROWD_RUNS:
                world = world_from_data(template, data)
                row[name], row["scans"] = run_crowd(world, seconds, steer, windowed, batch)
            rows.append(row)
    return rows
