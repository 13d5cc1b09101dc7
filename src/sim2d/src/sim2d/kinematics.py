"""Robot kinematics: holonomic and differential drive, velocity limits, collision and stall.

Pose layout everywhere: (x [m], y [m], yaw [rad]) in the map frame; body twist (vx, vy, wz) in
base_link [m/s, m/s, rad/s]; wheel speeds (left, right) [rad/s].
"""
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

HOLONOMIC, DIFFERENTIAL = "holonomic", "differential"
Pose = tuple[float, float, float]   # (x, y, yaw), or a body twist (vx, vy, wz)


@dataclass
class DriveLimits:
    """Velocity and acceleration limits of one robot."""

    max_linear: float = 0.5             # [m/s] |vx| (and |vy| for holonomic robots)
    max_angular: float = 1.0            # [rad/s] |wz|
    max_linear_accel: float = 1.0       # [m/s^2]
    max_angular_accel: float = 2.0      # [rad/s^2]


@dataclass
class WheelConfig:
    """Differential-drive wheels (thesis 002 Sec. 2.1.1: Penguin wheel radius 0.075 m)."""

    radius: float = 0.075               # [m]
    separation: float = 0.45            # [m] distance between the wheel contact points
    encoder_ticks_per_rev: int = 4096   # [-] encoder resolution at the wheel


@dataclass
class RobotState:
    pose: tuple = (0.0, 0.0, 0.0)       # (x, y, yaw) ground truth
    twist: tuple = (0.0, 0.0, 0.0)      # executed body twist (vx, vy, wz)
    command: tuple = (0.0, 0.0, 0.0)    # commanded body twist (vx, vy, wz)
    wheel_angles: list = field(default_factory=lambda: [0.0, 0.0])  # [rad] left, right
    stalled: bool = False               # the last step was blocked by an obstacle
    bumps: int = 0                      # number of steps blocked so far


def wrap_angle(angle: float) -> float:
    """Angle in [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def integrate_body_twist(pose: Sequence[float], vx: float, vy: float, wz: float,
                         dt: float) -> Pose:
    """Exact pose after moving with a constant body twist for dt (a circular arc when wz != 0)."""
    x, y, yaw = pose
    turn = wz * dt
    if abs(turn) < 1e-9:
        fx, fy = vx * dt, vy * dt
    else:
        s, c = math.sin(turn), math.cos(turn)
        fx = (vx * s + vy * (c - 1.0)) / wz
        fy = (vx * (1.0 - c) + vy * s) / wz
    cy, sy = math.cos(yaw), math.sin(yaw)
    return x + cy * fx - sy * fy, y + sy * fx + cy * fy, wrap_angle(yaw + turn)


def wheels_to_twist(left: float, right: float, wheels: WheelConfig) -> tuple[float, float]:
    """Differential drive: wheel speeds [rad/s] -> (v [m/s], w [rad/s])."""
    v = wheels.radius * (right + left) / 2.0
    w = wheels.radius * (right - left) / wheels.separation
    return v, w


def twist_to_wheels(v: float, w: float, wheels: WheelConfig) -> tuple[float, float]:
    """Differential drive: (v [m/s], w [rad/s]) -> wheel speeds (left, right) [rad/s]."""
    left = (v - w * wheels.separation / 2.0) / wheels.radius
    right = (v + w * wheels.separation / 2.0) / wheels.radius
    return left, right


def _approach(current: float, target: float, max_step: float) -> float:
    return current + max(-max_step, min(max_step, target - current))


def limit_twist(command: Sequence[float], current: Sequence[float], drive: str,
                limits: DriveLimits, dt: float) -> Pose:
    """Clamp the command to the speed limits and ramp toward it within the acceleration limits."""
    vx, vy, wz = command
    if drive == DIFFERENTIAL:
        vy = 0.0
    vx = max(-limits.max_linear, min(limits.max_linear, vx))
    vy = max(-limits.max_linear, min(limits.max_linear, vy))
    wz = max(-limits.max_angular, min(limits.max_angular, wz))
    return (_approach(current[0], vx, limits.max_linear_accel * dt),
            _approach(current[1], vy, limits.max_linear_accel * dt),
            _approach(current[2], wz, limits.max_angular_accel * dt))


def step_robot(state: RobotState, drive: str, limits: DriveLimits, radius: float,
               clearance: Callable[[float, float], float], dt: float,
               wheels: WheelConfig | None = None) -> RobotState:
    """Advance one robot by dt; a translation into an obstacle is refused (stall, bump).

    clearance(x, y) -> free distance [m] around a map point. The robot may still turn in place
    when blocked (its footprint is a circle).
    """
    twist = limit_twist(state.command, state.twist, drive, limits, dt)
    new_pose = integrate_body_twist(state.pose, *twist, dt)
    moving = abs(twist[0]) + abs(twist[1]) > 0.0
    if moving and clearance(new_pose[0], new_pose[1]) < radius:
        twist = (0.0, 0.0, twist[2])
        new_pose = (state.pose[0], state.pose[1], new_pose[2])
        state.stalled = True
        state.bumps += 1
    else:
        state.stalled = False
    state.pose, state.twist = new_pose, twist
    if drive == DIFFERENTIAL and wheels is not None:
        left, right = twist_to_wheels(twist[0], twist[2], wheels)
        state.wheel_angles[0] += left * dt
        state.wheel_angles[1] += right * dt
    return state
