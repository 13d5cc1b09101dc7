"""Expert demonstrator: drives from a start to the route oracle's goal as a teleoperating person
would (thesis 002 §3.3): smooth (v, ω) within the Penguin's limits, along the corridor centre
line, turning into a branch without stopping, then stopping facing along the new corridor.

The driver is simulator-agnostic: `ExpertDriver.command(pose)` is called once per laser scan with
the robot's pose and returns the command to record (the clean expert label) and the command to
execute (label + DART noise, Laskey et al. 2017). Poses are (x [m], y [m], yaw [rad]).
"""
import math
from dataclasses import dataclass

import numpy as np

from semantic_nav.instruction_classes import BACK, COUNT_CORNERS, STRAIGHT, get
from semnav_learning.route_oracle import goal_branch


@dataclass
class ExpertConfig:
    """Penguin limits (config/penguin.yaml) and how the person drives."""

    rate: float = 10.0               # commands per second (seed: 50 steps ≈ 5 s) [Hz]
    max_linear_speed: float = 0.4    # [m/s] Penguin §2.1.1
    max_angular_speed: float = 1.0   # [rad/s]
    max_linear_accel: float = 0.5    # [m/s^2]
    max_angular_accel: float = 2.0   # [rad/s^2]
    lookahead: float = 0.7           # pure-pursuit look-ahead distance [m]
    turn_slowdown: float = 0.8       # v = v_max / (1 + turn_slowdown * |curvature| [1/m])
    spin_angle: float = 100.0        # look-ahead further off the heading: turn on the spot [deg]
    spin_gain: float = 1.5           # on-the-spot turn rate per heading error [1/s]
    arrive_distance: float = 0.15    # path end this close: align heading, then stop [m]
    align_tolerance: float = 4.0     # heading error accepted at the goal [deg]
    stop_steps: int = 10             # zero commands before the expert *policy* moves on [1]
    stop_duration: float = 6.0       # standing still recorded at the end of a demonstration:
    #                                  > the 50 steps ≈ 5 s of the halting counter (§2.2.5.2,
    #                                  Fig. 3.3.1 records end with the robot standing) [s]
    noise_linear: float = 0.02       # std of the executed linear speed noise [m/s]
    noise_angular: float = 0.08      # std of the executed angular speed noise [rad/s]
    max_duration: float = 240.0      # give up after this long [s]


def recorded_stop_steps(config):
    """Zero commands recorded at the end of a demonstration at `config.rate`: the robot stands
    still for `stop_duration` (§2.2.5.2: halting needs 50 zero outputs ≈ 5 s at 10 Hz)."""
    return int(math.ceil(config.stop_duration * config.rate - 1e-9))


def expert_route(walk, label, goal_pose, counting=COUNT_CORNERS):
    """Polyline (N, 2) the person follows: centre line, junction centre, into the branch
    (`counting`: route_oracle.goal_branch's)."""
    origin = np.asarray(walk.origin, dtype=float)
    goal = np.array(goal_pose[:2], dtype=float)
    motion = get(label).motion
    if motion == BACK:
        return origin[None, :]
    if motion == STRAIGHT:
        return np.vstack([origin, goal])
    junction = walk.point(goal_branch(walk, label, counting).centre)
    return np.vstack([origin, junction, goal])


def _closest_arc_length(path, cumulative, xy, previous):
    """Arc length of the point of the path nearest to xy, never behind `previous`."""
    best, best_s = math.inf, previous
    for i in range(len(path) - 1):
        a, b = path[i], path[i + 1]
        seg = b - a
        length = float(np.hypot(*seg))
        t = float(np.clip(np.dot(xy - a, seg) / (length ** 2), 0.0, 1.0)) if length else 0.0
        d = float(np.hypot(*(a + t * seg - xy)))
        s = cumulative[i] + t * length
        if d < best and s >= previous - 0.05:
            best, best_s = d, s
    return max(best_s, previous)


def _point_at(path, cumulative, s):
    """Point of the polyline at arc length s (clamped to its ends)."""
    s = min(max(s, 0.0), cumulative[-1])
    i = min(int(np.searchsorted(cumulative, s, side="right")) - 1, len(path) - 2)
    seg_len = cumulative[i + 1] - cumulative[i]
    t = (s - cumulative[i]) / seg_len if seg_len else 0.0
    return path[i] + t * (path[i + 1] - path[i])


class ExpertDriver:
    """Pure pursuit along the expert route with a speed profile, then a final heading alignment."""

    def __init__(self, route, goal_pose, config=None, rng=None):
        self.config = config or ExpertConfig()
        self.path = np.asarray(route, dtype=float).reshape(-1, 2)
        if len(self.path) == 1:
            self.path = np.vstack([self.path, self.path])
        steps = np.hypot(*np.diff(self.path, axis=0).T)
        self.cumulative = np.concatenate([[0.0], np.cumsum(steps)])
        self.goal_yaw = float(goal_pose[2])
        self.rng = rng
        self.progress = 0.0
        self.command_now = (0.0, 0.0)
        self.arrived = False

    def _target(self, pose):
        """Unlimited (v, ω) wanted at this pose."""
        cfg = self.config
        x, y, yaw = pose
        self.progress = _closest_arc_length(self.path, self.cumulative, np.array([x, y]),
                                            self.progress)
        remaining = self.cumulative[-1] - self.progress
        end = self.path[-1]
        if self.arrived or math.hypot(end[0] - x, end[1] - y) < cfg.arrive_distance \
                or self.cumulative[-1] == 0.0:
            self.arrived = True
            error = math.remainder(self.goal_yaw - yaw, 2 * math.pi)
            return 0.0, cfg.spin_gain * error
        ahead = _point_at(self.path, self.cumulative, self.progress + cfg.lookahead)
        if remaining < cfg.lookahead:      # aim beyond the end along the goal heading
            ahead = end + (cfg.lookahead - remaining) * np.array(
                [math.cos(self.goal_yaw), math.sin(self.goal_yaw)])
        alpha = math.remainder(math.atan2(ahead[1] - y, ahead[0] - x) - yaw, 2 * math.pi)
        if abs(alpha) > math.radians(cfg.spin_angle):
            return 0.0, cfg.spin_gain * alpha
        curvature = 2.0 * math.sin(alpha) / cfg.lookahead
        v = cfg.max_linear_speed / (1.0 + cfg.turn_slowdown * abs(curvature))
        v = min(v, math.sqrt(2.0 * cfg.max_linear_accel * 0.5 * max(remaining, 0.0)))
        return v, v * curvature

    def command(self, pose):
        """-> (label (v, ω), executed (v, ω), done). Limits: speeds, accelerations."""
        cfg = self.config
        dt = 1.0 / cfg.rate
        v, w = self._target(pose)
        v = float(np.clip(v, 0.0, cfg.max_linear_speed))
        if abs(w) > cfg.max_angular_speed:    # keep the curvature, slow down
            v *= cfg.max_angular_speed / abs(w)
            w = math.copysign(cfg.max_angular_speed, w)
        v0, w0 = self.command_now
        v = float(np.clip(v, v0 - cfg.max_linear_accel * dt, v0 + cfg.max_linear_accel * dt))
        w = float(np.clip(w, w0 - cfg.max_angular_accel * dt, w0 + cfg.max_angular_accel * dt))
        done = self.arrived and abs(math.remainder(self.goal_yaw - pose[2], 2 * math.pi)) \
            < math.radians(cfg.align_tolerance) and abs(v) < 1e-3
        if done:
            v, w = 0.0, 0.0
        self.command_now = (v, w)
        executed = (v, w)
        if self.rng is not None and not done:
            executed = (max(0.0, v + self.rng.normal(0.0, cfg.noise_linear)),
                        w + self.rng.normal(0.0, cfg.noise_angular))
        return (v, w), executed, done


def unicycle_step(pose, v, w, dt, substeps=5):
    """Exact-enough differential-drive integration of (v, ω) over dt (for tests and benchmarks;
    demonstrations for the dataset are driven in sim2d)."""
    x, y, yaw = pose
    h = dt / substeps
    for _ in range(substeps):
        x += v * h * math.cos(yaw + 0.5 * w * h)
        y += v * h * math.sin(yaw + 0.5 * w * h)
        yaw += w * h
    return (x, y, math.remainder(yaw, 2 * math.pi))


@dataclass
class Rehearsal:
    """One demonstration driven with unicycle kinematics on the occupancy grid."""

    poses: np.ndarray       # (N, 3) pose before each command
    labels: np.ndarray      # (N, 2) recorded expert commands (v, ω)
    reached: bool           # final pose inside the goal region
    min_clearance: float    # closest approach of the robot centre to an obstacle [m]


def rehearse(oracle, start, label, config=None, rng=None, start_offset=(0.0, 0.0, 0.0),
             walk=None):
    """Drive class `label` from `start` (optionally displaced) with the expert and unicycle
    kinematics; None when the class is not applicable here. `walk`: oracle.walk(start) when
    the caller has it (every class from one start needs the same walk, the costly part)."""
    config = config or ExpertConfig()
    walk = oracle.walk(start) if walk is None else walk
    goal = oracle.goal(start, label, walk)
    if goal is None:
        return None
    driver = ExpertDriver(expert_route(walk, label, goal.pose), goal.pose, config, rng)
    pose = tuple(float(a + b) for a, b in zip(start, start_offset))
    poses, labels, stopped = [], [], 0
    for _ in range(int(config.max_duration * config.rate)):
        label_cmd, executed, done = driver.command(pose)
        poses.append(pose)
        labels.append(label_cmd)
        stopped = stopped + 1 if done else 0
        if stopped >= recorded_stop_steps(config):
            break
        pose = unicycle_step(pose, *executed, 1.0 / config.rate)
    poses = np.array(poses)
    clearance = min(oracle.field.at(x, y) for x, y, _ in poses)
    return Rehearsal(poses, np.array(labels), goal.contains(*poses[-1]) and stopped > 0,
                     clearance)
