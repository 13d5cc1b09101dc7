"""DWA-style local controller (Fox, Burgard & Thrun 1997; ROS dwa_local_planner's cost terms).

ROS-free. Each control cycle samples velocities (vx, vy, wz) in the dynamic window reachable from
the current velocity within one control period, rolls each out at constant velocity for sim_time,
and scores the trajectory as dwa_local_planner does:
    cost = path_distance_bias * d(end, path) + goal_distance_bias * d(end, local goal)
         + path_distance_bias * d(front, path) + goal_distance_bias * d(front, local goal)
         + occdist_scale * max costmap cost along the trajectory,
where `front` is a point forward_point_distance ahead of the end pose (it aligns the heading) and
the obstacle cost comes from the clearance of the trajectory's poses. That clearance is, by
default (clearance_model "continuous"), clearance.ContactClearance: the Euclidean distance of
each pose into the region where the grid contact test passes (a lower bound within 7 mm on
0.05 m cells), plus the distance to laser hits of obstacles not on the map; trajectories that
come within contact_margin of contact are discarded.
With clearance_model "cells" it is LocalCostmap: a cell lookup of a rolling-window distance
transform of the map and the live laser hits, and the discarded trajectories are those passing
within the inscribed radius, never taken smaller than the contact clearance.
"""
import math
from dataclasses import dataclass

import numpy as np

from nav_mocks.costmap import (CostmapConfig, contact_clearance, inflation_cost,
                               obstacle_distance)
from nav_mocks.pose2d import wrap_angle

ALIGNMENT_OFF_FACTOR = 2.0  # [-] alignment terms off within this many forward-point distances
CLEARANCE_MODELS = ("continuous", "cells")
LATE_COLLISION_COST = 1e3   # [-] ranks trajectories that would collide after a stop behind all


@dataclass
class DwaConfig:
    """Names follow dwa_local_planner / base_local_planner parameters."""

    max_vel_x: float = 0.5            # [m/s]
    min_vel_x: float = 0.0            # [m/s] negative: the base may reverse
    max_vel_y: float = 0.0            # [m/s] lateral speed; > 0 only for a holonomic base
    max_vel_theta: float = 1.5        # [rad/s]
    acc_lim_x: float = 2.0            # [m/s^2]
    acc_lim_y: float = 2.0            # [m/s^2]
    acc_lim_theta: float = 4.0        # [rad/s^2]
    control_period: float = 0.1       # [s] one controller cycle: the dynamic window's time
    sim_time: float = 1.5             # [s] rollout horizon
    sim_granularity: float = 0.1      # [s] rollout step
    vx_samples: int = 7               # [-]
    vy_samples: int = 5               # [-] used when max_vel_y > 0
    vth_samples: int = 15             # [-]
    path_distance_bias: float = 32.0  # [1/m] weight of the distance to the global plan
    goal_distance_bias: float = 24.0  # [1/m] weight of the distance to the local goal
    occdist_scale: float = 0.01       # [1/cost] weight of the largest costmap cost on the way
    forward_point_distance: float = 0.325  # [m] heading-alignment point ahead of the robot
    local_goal_distance: float = 2.0  # [m] how far along the plan the local goal lies
    local_window: float = 5.0         # [m] side of the rolling local costmap
    fused_scans: int = 1              # [-] latest scans whose median clearance the local
                                      # costmap uses (1: the last scan only)
    xy_goal_tolerance: float = 0.1    # [m]
    yaw_goal_tolerance: float = 0.15  # [rad]
    rotate_gain: float = 2.0          # [1/s] in-place rotation rate per rad of yaw error
    contact_margin: float = 0.02      # [m] kept beyond the contact clearance (localisation error)
    clearance_model: str = "continuous"  # [-] "continuous": distance into the contact region
                                         # and to unmapped laser hits (clearance.py); "cells":
                                         # cell lookup of a local distance transform
    clearance_subdivision: int = 10   # [-] continuous model: the contact region's depth is
                                      # tabulated on cells this many times finer than the map

    @property
    def holonomic(self):
        return self.max_vel_y > 0

    def validate(self):
        if self.max_vel_x <= 0 or self.max_vel_theta <= 0 or self.min_vel_x > self.max_vel_x:
            raise ValueError("dwa: need max_vel_x > 0, max_vel_theta > 0, min_vel_x <= max_vel_x")
        if self.clearance_model not in CLEARANCE_MODELS:
            raise ValueError(f"dwa: clearance_model must be one of {CLEARANCE_MODELS}, "
                             f"got {self.clearance_model!r}")
        if self.clearance_subdivision < 1:
            raise ValueError(f"dwa: clearance_subdivision must be >= 1, "
                             f"got {self.clearance_subdivision}")
        if self.fused_scans < 1:
            raise ValueError(f"dwa: fused_scans must be >= 1, got {self.fused_scans}")
        if min(self.control_period, self.sim_time, self.sim_granularity) <= 0:
            raise ValueError("dwa: control_period, sim_time and sim_granularity must be > 0")


def velocity_window(current, config):
    """Dynamic window: reachable (vx, vy, wz) ranges within one control period, inside limits."""
    vx0, vy0, w0 = current
    dt = config.control_period
    ranges = [(vx0, config.acc_lim_x, config.min_vel_x, config.max_vel_x),
              (vy0, config.acc_lim_y, -config.max_vel_y, config.max_vel_y),
              (w0, config.acc_lim_theta, -config.max_vel_theta, config.max_vel_theta)]
    window = []
    for v, acc, low, high in ranges:
        lo, hi = max(low, v - acc * dt), min(high, v + acc * dt)
        if lo > hi:  # current speed beyond a limit (e.g. limits changed): brake towards it
            lo = hi = min(max(v, low), high)
        window.append((lo, hi))
    return window


def sample_velocities(current, config):
    """(S, 3) velocity samples spanning the dynamic window (zero included when inside it)."""
    counts = (config.vx_samples, config.vy_samples if config.holonomic else 1,
              config.vth_samples)
    axes = []
    for (lo, hi), n in zip(velocity_window(current, config), counts):
        values = np.linspace(lo, hi, max(n, 1)) if hi > lo else np.array([lo])
        if lo < 0.0 < hi:
            values = np.union1d(values, [0.0])
        axes.append(values)
    grid = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([g.ravel() for g in grid])


def rollout(pose, velocities, config):
    """Poses along constant-velocity trajectories: (S, T, 3) x, y, yaw in the map frame."""
    steps = max(1, int(round(config.sim_time / config.sim_granularity)))
    dt = config.sim_time / steps
    vx, vy, wz = (velocities[:, i:i + 1] for i in range(3))
    yaw = pose[2] + wz * dt * np.arange(steps)[None, :]            # heading at each step start
    dx = (vx * np.cos(yaw) - vy * np.sin(yaw)) * dt
    dy = (vx * np.sin(yaw) + vy * np.cos(yaw)) * dt
    x = pose[0] + np.cumsum(dx, axis=1)
    y = pose[1] + np.cumsum(dy, axis=1)
    return np.stack((x, y, yaw + wz * dt), axis=2)


class LocalCostmap:
    """Rolling window around the robot: map obstacles plus laser hits -> clearance [m].

    The laser hits may be one scan's or the last few scans' (a list, oldest first): each scan
    with the map gives a distance field, and the clearance of a cell is the lower median of
    those fields (fuse_scans). A single noisy beam, or a hit that range noise moved into the
    next cell, then no longer sets the clearance; an obstacle seen in most of the scans does.
    """

    def __init__(self, lethal, grid, center, points, side):
        """lethal: (H, W) bool global lethal mask on `grid`; points: (M, 2) laser hits [m], or a
        list of such arrays, one per scan."""
        res = grid.resolution
        half = int(math.ceil(0.5 * side / res))
        row0, col0 = grid.world_to_cell(center[0], center[1])
        self.row0, self.col0 = int(row0) - half, int(col0) - half
        size = 2 * half + 1
        window = np.zeros((size, size), dtype=bool)
        r_lo, c_lo = max(self.row0, 0), max(self.col0, 0)
        r_hi, c_hi = min(self.row0 + size, grid.height), min(self.col0 + size, grid.width)
        if r_hi > r_lo and c_hi > c_lo:
            window[r_lo - self.row0:r_hi - self.row0, c_lo - self.col0:c_hi - self.col0] = \
                lethal[r_lo:r_hi, c_lo:c_hi]
        scans = list(points) if isinstance(points, (list, tuple)) else [points]
        fields = []
        for scan_points in scans or [np.zeros((0, 2))]:
            marked = window.copy()
            if len(scan_points):
                rows, cols = grid.world_to_cell(scan_points[:, 0], scan_points[:, 1])
                rows, cols = rows - self.row0, cols - self.col0
                keep = (rows >= 0) & (rows < size) & (cols >= 0) & (cols < size)
                marked[rows[keep], cols[keep]] = True
            fields.append(obstacle_distance(marked) * res)          # [m]
        self.grid = grid
        self.distance = fuse_scans(np.stack(fields))

    def collision_radius(self, costmap_config, margin):
        """[m] cell-centre clearance a trajectory must keep: the padded radius, and never less
        than the contact clearance (a padding smaller than the cell bound does not count)."""
        return max(costmap_config.inscribed_radius,
                   contact_clearance(costmap_config.robot_radius, self.grid.resolution, margin))

    def clearance(self, x, y):
        """Distance [m] from map points to the nearest obstacle cell centre in the window."""
        rows, cols = self.grid.world_to_cell(x, y)
        rows, cols = rows - self.row0, cols - self.col0
        size = self.distance.shape[0]
        inside = (rows >= 0) & (rows < size) & (cols >= 0) & (cols < size)
        out = np.full(np.shape(rows), np.inf)
        out[inside] = self.distance[rows[inside], cols[inside]]
        return out


def fuse_scans(fields):
    """(K, H, W) distance fields, one per scan -> (H, W): the lower median over the scans.

    With three scans the middle value: an obstacle counts where at least two of them see it
    that close. With two, the smaller (no majority: keep the cautious one); with one, itself.
    """
    rank = (len(fields) - 1) // 2
    return np.partition(fields, rank, axis=0)[rank]


def local_plan(plan, pose, start_index, length):
    """Part of the global plan (N, 2) from the point nearest the robot to `length` metres on.

    The nearest point is searched from `start_index` on, so the robot never jumps back along a
    plan that doubles back near itself. Returns (segment (K, 2), index of its first point).
    """
    ahead = plan[start_index:]
    nearest = start_index + int(np.argmin(np.hypot(ahead[:, 0] - pose[0], ahead[:, 1] - pose[1])))
    steps = np.hypot(*np.diff(plan[nearest:], axis=0).T)
    travelled = np.concatenate(([0.0], np.cumsum(steps)))
    end = nearest + int(np.searchsorted(travelled, length, side="right"))
    return plan[nearest:max(end, nearest + 1)], nearest


def _point_set_distance(points, targets):
    """(S,) distance from each point (S, 2) to the nearest of `targets` (K, 2)."""
    diff = points[:, None, :] - targets[None, :, :]
    return np.sqrt((diff ** 2).sum(axis=2)).min(axis=1)


def _moves_away(clearance, here):
    """(S,) True where the first change of clearance along a trajectory is an increase.

    A robot already inside the inscribed radius may only translate away from the obstacle: a
    move along it at the same (cell-quantised) clearance is what leaves a robot wedged against a
    door jamb, since the true clearance there may be smaller than the estimate's.
    """
    changed = clearance != here
    first = np.argmax(changed, axis=1)
    return changed.any(axis=1) & (clearance[np.arange(len(clearance)), first] > here)


def score_trajectories(trajectories, segment, clearance, costmap_config, config, align=True):
    """dwa_local_planner cost of each trajectory; `align` adds the forward-point terms."""
    end = trajectories[:, -1, :]
    goal = segment[-1:]
    cost = (config.path_distance_bias * _point_set_distance(end[:, :2], segment)
            + config.goal_distance_bias * _point_set_distance(end[:, :2], goal))
    if align:
        front = end[:, :2] + config.forward_point_distance * np.column_stack(
            (np.cos(end[:, 2]), np.sin(end[:, 2])))
        cost += (config.path_distance_bias * _point_set_distance(front, segment)
                 + config.goal_distance_bias * _point_set_distance(front, goal))
    worst = clearance.min(axis=1)
    cost = cost + config.occdist_scale * inflation_cost(worst, costmap_config).astype(float)
    return cost


class DwaController:
    """Follows a global plan with DWA; one call to command() per control cycle."""

    def __init__(self, config=None, costmap_config=None):
        self.config = config or DwaConfig()
        self.config.validate()
        self.costmap_config = costmap_config or CostmapConfig()
        self.plan = None
        self.plan_index = 0

    def set_plan(self, plan_xy):
        """A new global plan: (N, 2) map-frame points from the robot to the goal."""
        plan_xy = np.asarray(plan_xy, dtype=float)
        if plan_xy.ndim != 2 or plan_xy.shape[1] != 2 or len(plan_xy) == 0:
            raise ValueError(f"dwa: plan must be a non-empty (N, 2) array, got {plan_xy.shape}")
        self.plan = plan_xy
        self.plan_index = 0

    def at_goal_xy(self, pose, goal):
        return math.hypot(goal[0] - pose[0], goal[1] - pose[1]) <= self.config.xy_goal_tolerance

    def rotate_to(self, pose, goal, velocity):
        """In-place rotation towards the goal yaw; (cmd, done)."""
        cfg = self.config
        error = wrap_angle(goal[2] - pose[2])
        if abs(error) <= cfg.yaw_goal_tolerance:
            return (0.0, 0.0, 0.0), True
        w0 = velocity[2]
        wanted = float(np.clip(cfg.rotate_gain * error, -cfg.max_vel_theta, cfg.max_vel_theta))
        step = cfg.acc_lim_theta * cfg.control_period
        return (0.0, 0.0, float(np.clip(wanted, w0 - step, w0 + step))), False

    def _collision_cost(self, samples, clearance, here, radius):
        """0 for collision-free trajectories; inf for inadmissible ones; a ranking penalty for
        those that would reach an obstacle only after the robot could have stopped.

        Fox et al.'s admissibility: the robot must be able to stop, at full deceleration and one
        control period late, before the first trajectory point inside the inscribed radius (a
        point may be inside only to move away from an obstacle the robot is already too close
        to). A trajectory that would collide later is still a safe command for this cycle, which
        matters at speed: the robot then slows down along an arc instead of coasting blindly.
        Among those, slower ones rank first.
        """
        cfg = self.config
        bad = (clearance <= radius) & (clearance < here)
        hits = bad.any(axis=1)
        speed = np.hypot(samples[:, 0], samples[:, 1])
        steps = clearance.shape[1]
        first = np.where(hits, np.argmax(bad, axis=1), steps)
        reach = speed * (first + 1) * (cfg.sim_time / steps)    # distance before the first bad
        braking = min(cfg.acc_lim_x, cfg.acc_lim_y if cfg.holonomic else cfg.acc_lim_x)
        stop = speed ** 2 / (2.0 * braking) + speed * cfg.control_period
        penalty = np.where(hits, LATE_COLLISION_COST * (1.0 + speed / cfg.max_vel_x), 0.0)
        inadmissible = hits & (reach <= stop)
        if here <= radius:
            inadmissible |= (speed > 0.0) & ~_moves_away(clearance, here)
        return np.where(inadmissible, np.inf, penalty)

    def collision_radius(self, local_costmap):
        """[m] clearance a trajectory must keep on this local map (LocalCostmap: the padded
        radius and at least the contact clearance; ContactClearance: contact_margin from
        contact)."""
        return local_costmap.collision_radius(self.costmap_config, self.config.contact_margin)

    def best_command(self, pose, velocity, local_costmap):
        """Best (vx, vy, wz) along the plan, or None when every trajectory collides."""
        cfg = self.config
        segment, self.plan_index = local_plan(self.plan, pose, self.plan_index,
                                              cfg.local_goal_distance)
        samples = sample_velocities(velocity, cfg)
        trajectories = rollout(pose, samples, cfg)
        clearance = local_costmap.clearance(trajectories[:, :, 0], trajectories[:, :, 1])
        here = float(local_costmap.clearance(np.array([pose[0]]), np.array([pose[1]]))[0])
        # As dwa_local_planner: no heading alignment near the goal, where the forward point
        # would overshoot it and leave a plateau of equal costs short of the goal.
        to_goal = math.hypot(self.plan[-1, 0] - pose[0], self.plan[-1, 1] - pose[1])
        align = to_goal > ALIGNMENT_OFF_FACTOR * cfg.forward_point_distance
        cost = score_trajectories(trajectories, segment, clearance, self.costmap_config, cfg,
                                  align)
        cost += self._collision_cost(samples, clearance, here, self.collision_radius(local_costmap))
        still = np.all(np.abs(samples) < 1e-9, axis=1)
        cost[still] = np.inf   # standing still is not a plan; no motion left means "blocked"
        best = int(np.argmin(cost))
        if not np.isfinite(cost[best]):
            return None
        return tuple(float(v) for v in samples[best])
