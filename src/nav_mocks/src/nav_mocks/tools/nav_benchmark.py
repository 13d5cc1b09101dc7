"""Navigation benchmark, ROS-free: the move_base core drives the sim2d world to random goals.

The household world of sim2d (config/worlds/household.yaml) is stepped in-process, as fast as the
CPU allows (no real-time pacing), without its people (the metric is collision with the map).
Each goal is a random free cell that the global planner can reach from where the robot stands;
the robot drives there from the previous goal. The core sees what move_base would see on the
robot: the AMCL mock's pose estimate, the odometry twist and the laser scan. Reported: success
rate, collisions (the simulator's bump counter: a refused move into the map), time per goal and
the ratio of driven length to the A* optimum (8-connected A* on the map inflated by the padded
robot radius, i.e. the shortest path the planner's free space allows).
"""
import math
import statistics
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from nav_mocks.amcl_model import AmclConfig, AmclModel
from floorplan.astar import astar
from nav_mocks.costmap import INSCRIBED_INFLATED_OBSTACLE, Costmap, CostmapConfig
from nav_mocks.dwa import DwaConfig
from nav_mocks.global_planner import GlobalPlanner, NoPath, PlannerConfig
from nav_mocks.move_base_core import ACTIVE, SUCCEEDED, MoveBaseConfig, MoveBaseCore
from nav_mocks.pose2d import between, compose
from nav_mocks.scan_rays import Scan
from sim2d.world import CACHE_DIR
from tamp_resources import resource

ROOT = resource()
MAX_GOAL_DRAWS = 10000   # [-] random cells tried for the next goal before the run gives up
# the executor rostests' drives: from the charging place (the world's start pose) to the dining
# room through its door and back to the alley
PLACE_ROUTE = ("alley", "dining_room", "charging_place", "dining_room", "alley", "dining_room",
               "alley")


@dataclass
class NavBenchConfig:
    goals: int = 200                     # [-] goals driven in sequence
    seed: int = 0                        # [-] goal draws and AMCL noise
    holonomic: bool = True               # [-] False: no lateral velocity samples
    localisation_noise: bool = True      # [-] False: the core sees the true pose
    world: Path = ROOT / "config" / "worlds" / "household.yaml"
    nav_config: Path = ROOT / "config" / "nav_mocks.yaml"
    sim_dt: float = 0.05                 # [s] simulator step
    timeout_base: float = 30.0           # [s] per-goal time limit: base + factor * optimum / v
    timeout_factor: float = 3.0          # [-]
    cache_dir: Path = CACHE_DIR


@dataclass
class GoalOutcome:
    status: int
    reason: str
    optimum_m: float
    driven_m: float
    seconds: float        # simulated
    bumps: int
    trace: list = field(default_factory=list)   # true (x, y) of the robot, once per cycle
    plan: object = None                         # (N, 2) first global plan


@dataclass
class NavBenchReport:
    outcomes: list = field(default_factory=list)
    wall_seconds: float = 0.0

    @property
    def success_rate(self):
        return sum(o.status == SUCCEEDED for o in self.outcomes) / max(len(self.outcomes), 1)

    @property
    def collisions(self):
        return sum(o.bumps > 0 for o in self.outcomes)

    def lines(self):
        done = [o for o in self.outcomes if o.status == SUCCEEDED]
        ratios = [o.driven_m / o.optimum_m for o in done if o.optimum_m > 0.2]
        out = [f"goals: {len(self.outcomes)}, succeeded: {len(done)} "
               f"({100 * self.success_rate:.1f} %), goals with a collision: {self.collisions}"]
        if ratios:
            out.append(f"path length / A* optimum: mean {statistics.mean(ratios):.3f}, "
                       f"median {statistics.median(ratios):.3f}, max {max(ratios):.3f} "
                       f"(goals farther than 0.2 m)")
            out.append(f"time per goal (simulated): mean "
                       f"{statistics.mean(o.seconds for o in done):.1f} s; "
                       f"driven {sum(o.driven_m for o in done):.0f} m in total")
        out.append(f"wall time: {self.wall_seconds:.0f} s")
        for i, o in enumerate(self.outcomes):
            if o.status != SUCCEEDED or o.bumps:
                out.append(f"  goal {i}: status {o.status} bumps {o.bumps}: {o.reason}")
        return out


def load_nav_configs(path, holonomic):
    """The move_base section of config/nav_mocks.yaml as core config objects."""
    section = yaml.safe_load(Path(path).read_text())["move_base"]
    pick = {k: v for k, v in section.items() if k in MoveBaseConfig.__dataclass_fields__}
    dwa = DwaConfig(**section["DWAPlannerROS"])
    if not holonomic:
        dwa.max_vel_y = 0.0
    return (CostmapConfig(**section["costmap"]), MoveBaseConfig(**pick), dwa,
            PlannerConfig(**section["planner"]), float(section["controller_frequency"]))


def load_amcl_config(path):
    """The amcl section of config/nav_mocks.yaml as an AmclConfig (other keys are node-only)."""
    section = yaml.safe_load(Path(path).read_text())["amcl"]
    return AmclConfig(**{k: v for k, v in section.items() if k in AmclConfig.__dataclass_fields__})


class NavigationBenchmark:
    def __init__(self, config):
        from sim2d.world import World   # the simulator is only needed here
        self.config = config
        self.world = World.from_file(config.world, cache_dir=config.cache_dir)
        self.world.people = []
        self.robot = self.world.robots[0]
        costmap_cfg, mb_cfg, dwa_cfg, planner_cfg, rate = load_nav_configs(config.nav_config,
                                                                            config.holonomic)
        self.control_period = 1.0 / rate
        dwa_cfg.control_period = self.control_period
        self.core = MoveBaseCore(Costmap(self.world.grid, costmap_cfg), mb_cfg, dwa_cfg,
                                 planner_cfg)
        noise = load_amcl_config(config.nav_config)
        if not config.localisation_noise:
            noise.noise_xy_std = noise.noise_yaw_std = 0.0
        self.amcl = AmclModel(noise, seed=config.seed)
        self.rng = np.random.default_rng(config.seed)
        costs = self.core.costmap.costs()
        self.blocked = costs >= INSCRIBED_INFLATED_OBSTACLE
        self.candidates = np.argwhere(~self.blocked)
        self.mount = self.robot.laser_mounts[0].mount
        self.angles = self.robot.lasers[0].model.beam_angles()
        self.scan_pose = None      # true pose at which the latest unused scan was taken

    def _draw_goal(self, pose):
        """A random free cell the global planner reaches from `pose`; its A* optimum [m] (plain
        A* over the planner's free cells, with the planner's way out of a blocked start)."""
        grid = self.world.grid
        start = tuple(int(v) for v in grid.world_to_cell(pose[0], pose[1]))
        blocked = self.core.planner.blocked_cells(pose[:2])
        for _ in range(MAX_GOAL_DRAWS):
            row, col = self.candidates[self.rng.integers(len(self.candidates))]
            x, y = (float(v) for v in grid.cell_to_world(row, col))
            try:
                self.core.make_plan(pose, (x, y))
            except NoPath:
                continue
            best = astar(blocked, start, (int(row), int(col)), grid.resolution)
            if best is not None:
                yaw = float(self.rng.uniform(-math.pi, math.pi))
                return (x, y, yaw), best.length_m
        raise RuntimeError(f"benchmark: no reachable goal in {MAX_GOAL_DRAWS} draws from "
                           f"({pose[0]:.2f}, {pose[1]:.2f})")

    def _sim_step(self):
        """One simulator step; remembers the pose of a new scan. Returns the distance moved."""
        before = self.robot.state.pose
        count = self.robot.scans[0].count if self.robot.scans[0] is not None else 0
        self.world.step(self.config.sim_dt)
        after = self.robot.state.pose
        if self.robot.scans[0] is not None and self.robot.scans[0].count != count:
            self.scan_pose = after
        return math.hypot(after[0] - before[0], after[1] - before[1])

    def _scan(self):
        model = self.robot.lasers[0].model
        ranges = np.asarray(self.robot.scans[0].ranges, dtype=float)
        return Scan(self.angles, ranges, model.range_min, model.range_max)

    def drive(self, goal, optimum):
        cfg = self.config
        start_time, bumps0 = self.world.time, self.robot.state.bumps
        speed = self.core.controller.config.max_vel_x
        limit = cfg.timeout_base + cfg.timeout_factor * optimum / speed
        pose = self.robot.state.pose
        self.core.start_goal(goal, self.world.time, self.amcl.estimate(self.world.time, pose)[0])
        driven, result, trace, first_plan = 0.0, None, [], None
        substeps = max(1, int(round(self.control_period / cfg.sim_dt)))
        while self.world.time - start_time < limit:
            truth = self.robot.state.pose
            estimate = self.amcl.estimate(self.world.time, truth)[0]
            if self.scan_pose is not None:
                # the scan was taken at scan_pose; place it with the estimate's current error,
                # as move_base looks tf up at the scan's stamp
                error = between(truth, estimate)
                self.core.observe(self._scan(), compose(compose(self.scan_pose, error), self.mount))
                self.scan_pose = None
            result = self.core.step(self.world.time, estimate, self.robot.state.twist)
            self.world.set_twist(self.robot.name, *result.cmd)
            trace.append(truth[:2])
            if first_plan is None and result.new_plan is not None:
                first_plan = result.new_plan.points
            if result.status != ACTIVE:
                break
            for _ in range(substeps):
                driven += self._sim_step()
        else:
            self.core.cancel("benchmark time limit")
            result = None
        self.world.set_twist(self.robot.name, 0.0, 0.0, 0.0)
        for _ in range(int(1.0 / cfg.sim_dt)):   # let the robot come to rest
            self._sim_step()
        status = result.status if result else -1
        reason = result.reason if result else f"time limit {limit:.0f} s"
        return GoalOutcome(status, reason, optimum, driven, self.world.time - start_time,
                           self.robot.state.bumps - bumps0, trace, first_plan)


def run_navigation_benchmark(config, progress=False):
    import time
    started = time.perf_counter()
    bench = NavigationBenchmark(config)
    report = NavBenchReport()
    for i in range(config.goals):
        goal, optimum = bench._draw_goal(bench.robot.state.pose)
        outcome = bench.drive(goal, optimum)
        report.outcomes.append(outcome)
        if progress:
            print(f"goal {i}: status {outcome.status} optimum {optimum:.2f} m driven "
                  f"{outcome.driven_m:.2f} m in {outcome.seconds:.1f} s bumps {outcome.bumps} "
                  f"{outcome.reason}", flush=True)
    report.wall_seconds = time.perf_counter() - started
    return report


@dataclass
class PlaceLeg:
    start: str
    goal: str
    outcome: GoalOutcome
    recoveries: list      # recovery behaviours run, in order


def load_places(graph_path):
    """{place name: (x, y, yaw)} from a topological graph YAML (maps/household.graph.yaml)."""
    nodes = yaml.safe_load(Path(graph_path).read_text())["nodes"]
    return {node["name"]: tuple(float(v) for v in node["pose"]) for node in nodes}


def run_place_tour(config, graph_path, route=PLACE_ROUTE, start="charging_place"):
    """Drive the robot from place to place (the places' poses of the graph); the robot starts
    where the world puts it (`start` names that place). The time limit of a leg follows
    NavBenchConfig from the length of a plan on the static map (the core's own planner may see
    laser marks). Returns [PlaceLeg]."""
    bench = NavigationBenchmark(config)
    static = GlobalPlanner(Costmap(bench.world.grid, bench.core.costmap.config),
                           bench.core.planner.config)
    places = load_places(graph_path)
    legs, here = [], start
    for name in route:
        goal = places[name]
        outcome = bench.drive(goal, static.plan(bench.robot.state.pose[:2], goal[:2]).length_m)
        legs.append(PlaceLeg(here, name, outcome, list(bench.core.run.history)))
        here = name
    return legs
