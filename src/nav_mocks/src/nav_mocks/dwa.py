"""DWA-style local controller (Fox, Burgard & Thrun 1997; ROS dwa_local_planner's cost terms).

ROS-free. Each control cycle samples velocities (vx, vy, wz) in the dynamic window reachable from
the current velocity within one control period, rolls each out at constant velocity for sim_time,
and scores the trajectory as dwa_local_planner does:
    cost = path_distance_bias * d(end, path) + goal_distance_bias * g(end)
         + path_distance_bias * d(front, path) + goal_distance_bias * g(front)
         + occdist_scale * max costmap cost along the trajectory,
where g is the distance to the local goal by way of the plan (goal_distance_via_plan, standing
in for dwa_local_planner's wavefront distance), `front` is a point forward_point_distance ahead
of the end pose (it aligns the heading) and the obstacle cost comes from the clearance of the
trajectory's poses: clearance.ContactClearance, the Euclidean distance of each pose into the
region where the grid contact test passes (a lower bound within 7 mm on 0.05 m cells), plus the
distance to laser hits of obstacles not on the map; trajectories that come within
contact_margin of contact are discarded.
"""
import math
from dataclasses import dataclass

import numpy as np

from nav_mocks.costmap import CostmapConfig, inflation_cost
from nav_mocks.pose2d import wrap_angle

ALIGNMENT_OFF_FACTOR = 2.0  # [-] alignment terms off within this many forward-point distances
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
    xy_goal_tolerance: float = 0.1    # [m]
    yaw_goal_tolerance: float = 0.15  # [rad]
    rotate_gain: float = 2.0          # [1/s] in-place rotation rate per rad of yaw error
    contact_margin: float = 0.02      # [m] kept beyond the contact clearance (localisation error)
    clearance_subdivision: int = 10   # [-] the contact region's depth is tabulated on cells
                                      # this many times finer than the map

    @property
    def holonomic(self):
        return self.max_vel_y > 0

    def validate(self):
        if self.max_vel_x <= 0 or self.max_vel_theta <= 0 or self.min_vel_x > self.max_vel_x:
            raise ValueError("dwa: need max_vel_x > 0, max_vel_theta > 0, min_vel_x <= max_vel_x")
        if self.clearance_subdivision < 1:
            raise ValueError(f"dwa: clearance_subdivision must be >= 1, "
                             f"got {self.clearance_subdivision}")
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


def goal_distance_via_plan(points, segment):
    """(S,) distance from each point (S, 2) to the local goal (the segment's last point) by way
    of the plan: |p - s_k| + (plan length from s_k to the goal), s_k the segment point nearest p.

    dwa_local_planner's goal distance is a wavefront (grid) distance on the local costmap, which
    goes round walls; the straight-line distance does not. Where the plan folds round a wall
    (south along a corridor, then west through a door, then north behind the wall), the local
    goal lies beyond the wall and moving along the plan takes the robot away from it in a
    straight line: the straight-line term then holds the robot still (a rotation in place
    scores best; docs/nav_mocks/RESULTS.md, "Door passage"). Along the plan this distance falls
    by every metre driven; for a straight plan with p on it, it equals the straight-line
    distance."""
    steps = np.hypot(*np.diff(segment, axis=0).T)
    remaining = np.concatenate((np.cumsum(steps[::-1])[::-1], [0.0]))   # [m] s_k -> goal
    diff = points[:, None, :] - segment[None, :, :]
    distance = np.sqrt((diff ** 2).sum(axis=2))
    nearest = np.argmin(distance, axis=1)
    rows = np.arange(len(points))
    return distance[rows, nearest] + remaining[nearest]


def _moves_away(clearance, here):
    """(S,) True where the first change of clearance along a trajectory is an increase.

    A robot already inside the collision radius may only translate away from the obstacle: a
    move along it at the same clearance is what leaves a robot wedged against a door jamb,
    since the true clearance there may be smaller than the estimate's.
    """
    changed = clearance != here
    first = np.argmax(changed, axis=1)
    return changed.any(axis=1) & (clearance[np.arange(len(clearance)), first] > here)


def score_trajectories(trajectories, segment, clearance, costmap_config, config, align=True):
    """dwa_local_planner cost of each trajectory; `align` adds the forward-point terms."""
    end = trajectories[:, -1, :]
    cost = (config.path_distance_bias * _point_set_distance(end[:, :2], segment)
            + config.goal_distance_bias * goal_distance_via_plan(end[:, :2], segment))
    if align:
        front = end[:, :2] + config.forward_point_distance * np.column_stack(
            (np.cos(end[:, 2]), np.sin(end[:, 2])))
        cost += (config.path_distance_bias * _point_set_distance(front, segment)
                 + config.goal_distance_bias * goal_distance_via_plan(front, segment))
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
        """[m] clearance a trajectory must keep on this local map (ContactClearance:
        contact_margin from contact)."""
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
