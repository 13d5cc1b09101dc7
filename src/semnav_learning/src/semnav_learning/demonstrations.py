"""Expert demonstrations in the sim2d world, recorded in penguin_base's record format
(thesis 002 §3.3.1): one (velocity, laser ranges) sample per laser scan, from the start pose to
the route oracle's goal of one instruction class."""
import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from penguin_base.recording import SequenceBuilder
from semnav_learning.episodes import EpisodeError, chain_applies, chain_goals
from semnav_learning.expert import ExpertConfig, ExpertDriver, recorded_stop_steps
from semantic_nav.instruction_classes import CLASS_IDS, COUNT_CORNERS, COUNT_SIDE, COUNTING_IDS
from semnav_learning.route_oracle import RouteOracle, counting_matters
from sim2d.kinematics import RobotState
from floorplan.occupancy_map import load_map
from sim2d.world import CACHE_DIR, World, new_odometry
from sim2d.world_config import load_world_config

RANGE_DECIMALS = 3   # ranges written to the mm (the UTM-30LX is ±30 mm): ~3x smaller files


@dataclass
class Demonstration:
    """One driven demonstration and how it ended."""

    sequence: object        # penguin_base RecordSequence (class, samples)
    reached: bool           # final pose inside the oracle's goal region
    bumps: int              # steps the simulator blocked against an obstacle
    final_pose: tuple       # (x, y, yaw)

    @property
    def ok(self):
        return self.reached and self.bumps == 0


def floor_map_path(name, maps_dir):
    """A floor named on a command line -> its map YAML: a path ending in .yaml as given, else
    `maps_dir`/<name>.yaml (the hand-made floors)."""
    return Path(name) if str(name).endswith(".yaml") else Path(maps_dir) / f"{name}.yaml"


def world_for_floor(template, map_path, laser_dir=None, cache_dir=CACHE_DIR, raycast=None):
    """A sim2d World of `template` (config/worlds/*.yaml: robot, laser) on another floor, the
    robot where that floor is most open (the template's pose belongs to its own floor; episodes
    and demonstrations place the robot themselves). raycast: "table" / "march" overrides the
    template's lasers; cache_dir None: the range table is not cached (a one-off floor)."""
    config = load_world_config(template, laser_dir)
    config.map_path = Path(map_path).resolve()
    config.graph_path = None
    config.people, config.objects = [], []
    for robot in config.robots:
        robot.pose = sample_free_pose(config.map_path)
        for laser in robot.lasers:
            laser.raycast = raycast or laser.raycast
    return World(config, cache_dir)


def sample_free_pose(map_path):
    """The pose of most clearance on the floor (a World needs its robot somewhere free)."""
    clearance = RouteOracle(load_map(map_path)).field
    row, col = np.unravel_index(np.argmax(clearance.clearance), clearance.clearance.shape)
    x, y = clearance.grid.cell_to_world(row, col)
    return (float(x), float(y), 0.0)


def _reset(world, robot, pose, laser_index):
    robot.state = RobotState(pose=tuple(float(v) for v in pose))
    robot.odometry = new_odometry(robot.config, pose)
    robot.next_scan[laser_index] = world.time + robot.lasers[laser_index].model.scan_time


def demonstrate(world, robot_name, oracle, start, label, config=None, rng=None, laser_index=0,
                start_offset=(0.0, 0.0, 0.0), record_rate=None, after=(),
                counting=COUNT_CORNERS):
    """Drive class `label` from `start` in the world, recording every scan (or, with
    `record_rate` [Hz], one scan cast per period: the 10 Hz of control instead of the laser's
    40 Hz); None if the class is not applicable from this start.

    after: classes of the earlier parts of a chained instruction (episodes.chain_goals), not
    driven: the demonstration starts where they end (e.g. after=(1,), label 3: "turn left",
    standing at the end of the corridor that "go straight to the end" followed); `counting`:
    how class `label` counts (instruction_classes.COUNTINGS, route_oracle.goal_branch)."""
    try:
        parts = chain_goals(oracle, start, (*after, label),
                            (COUNT_CORNERS,) * len(after) + (counting,))
    except EpisodeError:
        return None
    goal, route = parts[-1].goal, parts[-1].route
    if after:
        start = parts[-2].goal.pose
    robot = world.robot(robot_name)
    scan_time = 1.0 / record_rate if record_rate else robot.lasers[laser_index].model.scan_time
    config = dataclasses.replace(config or ExpertConfig(), rate=1.0 / scan_time)
    driver = ExpertDriver(route, goal.pose, config, rng)
    _reset(world, robot, [a + b for a, b in zip(start, start_offset)], laser_index)
    if record_rate:      # the world's own scans are not used: do not cast them
        robot.next_scan[laser_index] = math.inf
    builder = SequenceBuilder(velocity_source="cmd_vel")
    builder.on_instruction_class(label)
    ranges = robot.lasers[laser_index].scan(robot.state.pose)
    stopped = 0
    for _ in range(int(config.max_duration * config.rate)):
        label_cmd, executed, done = driver.command(robot.state.pose)
        builder.on_velocity("cmd_vel", *label_cmd)
        builder.on_scan(np.round(np.asarray(ranges, dtype=np.float64), RANGE_DECIMALS))
        stopped = stopped + 1 if done else 0
        if stopped >= recorded_stop_steps(config):
            break
        world.set_twist(robot_name, executed[0], 0.0, executed[1])
        world.step(scan_time)
        scan = robot.scans[laser_index]
        ranges = scan.ranges if scan is not None and math.isclose(
            scan.stamp, world.time, abs_tol=1e-6) else \
            robot.lasers[laser_index].scan(robot.state.pose)
    builder.on_instruction_class(0)
    pose = robot.state.pose
    return Demonstration(builder.finish()[0], goal.contains(*pose) and stopped > 0,
                         robot.state.bumps, tuple(pose))


def plan_demonstrations(oracle, starts, per_class, rng):
    """Balance the classes: for each class, up to `per_class` of the starts from which it is
    applicable, drawn at random. Returns [(start, class)] in class order."""
    applicable = {label: [] for label in CLASS_IDS}
    for start in starts:
        for label, goal in oracle.goals(start).items():
            if goal is not None:
                applicable[label].append(start)
    plan = []
    for label, candidates in applicable.items():
        chosen = rng.permutation(len(candidates))[:per_class]
        plan.extend((candidates[i], label) for i in sorted(chosen))
    return plan


def plan_counting_demonstrations(oracle, starts, per_class, rng):
    """Classes 5-8 from starts where counting the corners over both sides matters
    (route_oracle.counting_matters): for each class, up to `per_class` of those starts, drawn at
    random. Returns [(start, class)] in class order."""
    plan = []
    walks = [oracle.walk(start) for start in starts]
    for label in COUNTING_IDS:
        candidates = [start for start, walk in zip(starts, walks)
                      if counting_matters(walk, label)]
        chosen = rng.permutation(len(candidates))[:per_class]
        plan.extend((candidates[i], label) for i in sorted(chosen))
    return plan


def plan_side_demonstrations(oracle, starts, per_class, rng):
    """Beyond the seed: classes 5-8 counted on their side only ("take the second right") from
    starts where that reaches another branch than counting the corners over both sides, so a
    network given the counting mode learns both counts: for each class, up to `per_class` of
    those starts, drawn at random. Returns [(start, class)] in class order."""
    plan = []
    walks = [oracle.walk(start) for start in starts]
    for label in COUNTING_IDS:
        candidates = [start for start, walk in zip(starts, walks)
                      if counting_matters(walk, label)
                      and chain_applies(oracle, start, (label,), (COUNT_SIDE,))]
        chosen = rng.permutation(len(candidates))[:per_class]
        plan.extend((candidates[i], label) for i in sorted(chosen))
    return plan
