"""Collision guard (beyond the seed): the last stage before /cmd_vel slows the network's moving
velocity so that the robot's circular footprint never reaches a laser return.

The seed names drifting into side walls and accumulated small errors as its failure modes
(thesis 002 §4.2.2); most failed evaluation episodes end in a wall. guard_velocity keeps the
network's rotating velocity and only limits v: the robot is a circle, so turning in place
cannot touch a wall, and the network sees the next scan and can steer out. It rolls the
commanded arc (v, ω) forward over `horizon` seconds, finds the free path length s before the
footprint plus `margin` would touch a return, and sends v' = sgn(v) · min(|v|, s / horizon):
full speed in the open, a smooth approach to a wall, and a stop at the margin. Given the ω the
base is turning at (the last command sent), the path checked is the one the base drives while
its ω moves to the new one at `angular_accel`, not the commanded arc: a base that still turns
the other way first swings towards what the new arc avoids.

Reversing is blocked unless `allow_reverse`: the Penguin's lasers do not see behind it (UTM-30LX
270°, URG-04LX 240°), and the expert never reverses, so a negative v is a regression artefact
that backs the robot into a wall it cannot see (all 5 collisions left with the guard on the
1,000 test episodes were such reversals while turning).

Steering round a blocked arc (`steer`, on by default; `steer_around`): where the guard would
stop a robot the network wants to move, it tries the nearest rotating velocities instead, and
turns the robot in place if no arc is free. Without it a robot that cut a corner stands before
the wall: the network either gives up, so the halting counter ends the instruction short of the
goal, or its ω dithers round zero until the episode times out (EVALUATION.md, "Steering round
a blocked arc").
"""
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from semantic_nav.laser_layer import LaserModel

Points = NDArray[np.float64]   # (M, 2) laser returns in the base frame (scan_points)


@dataclass
class GuardConfig:
    """Footprint and look-ahead of the guard."""

    enabled: bool = True
    radius: float = 0.3        # footprint radius of the Penguin (sim2d: circle of 0.3 m) [m]
    margin: float = 0.05       # kept free around the footprint [m]
    horizon: float = 1.0       # look-ahead along the commanded arc, and the approach time [s]
    resolution: float = 0.05   # time between checked poses on the arc [s]
    laser_x: float = 0.0       # laser ahead of the base centre (Penguin: mounted on it) [m]
    allow_reverse: bool = False   # True only for a laser that sees behind the robot
    angular_accel: float = 2.0    # the base reaches a new ω at this rate (Penguin's
    #                               max_angular_accel); 0: at once [rad/s^2]
    steer: bool = True         # a blocked arc: try the nearest ω that lets the robot move
    steer_range: float = 1.0   # largest |ω| tried (the Penguin's max_angular) [rad/s]
    steer_step: float = 0.1    # spacing of the ω tried [rad/s]
    steer_speed: float = 0.1   # an arc is usable from this guarded speed (or the command's) [m/s]
    steer_turn: float = 0.5    # no arc usable: turn in place at this rate, away from the
    #                            nearest return ahead [rad/s]


def scan_points(ranges: ArrayLike, laser: "LaserModel", laser_x: float = 0.0) -> Points:
    """Valid returns of one scan of `laser` (laser_layer.LaserModel) as (M, 2) points in the base
    frame (x forward, y left); NaN, out-of-range and "no return" readings are dropped."""
    ranges = np.asarray(ranges, dtype=float)
    angles = laser.angle_min + laser.angle_increment * np.arange(ranges.size)
    valid = np.isfinite(ranges) & (ranges >= laser.range_min) & (ranges < laser.range_max)
    r, a = ranges[valid], angles[valid]
    return np.column_stack((laser_x + r * np.cos(a), r * np.sin(a)))


def arc_positions(v: float, w: float, times: ArrayLike) -> NDArray[np.float64]:
    """Unicycle positions (x, y) after `times` [s] at constant (v, ω) from the origin facing +x."""
    times = np.asarray(times, dtype=float)
    if abs(w) < 1e-9:
        return np.column_stack((v * times, np.zeros_like(times)))
    return np.column_stack((v / w * np.sin(w * times), v / w * (1.0 - np.cos(w * times))))


def ramped_arc_positions(v: float, w: float, w_now: float, accel: float,
                         times: ArrayLike) -> NDArray[np.float64]:
    """Unicycle positions (x, y) after `times` [s] (an even grid from 0) at speed v from the
    origin facing +x, while ω goes from `w_now` to `w` at `accel` [rad/s^2] and then stays.
    The heading is integrated at each interval's midpoint."""
    times = np.asarray(times, dtype=float)
    dt = times[1] - times[0] if len(times) > 1 else 0.0
    change = w - w_now
    ramp = abs(change) / accel           # time to reach w

    def heading(t: NDArray[np.float64]) -> NDArray[np.float64]:
        t_ramp = np.minimum(t, ramp)
        return w_now * t + math.copysign(0.5 * accel, change) * t_ramp ** 2 \
            + change * np.maximum(t - ramp, 0.0)

    mid = heading(times[:-1] + 0.5 * dt)
    steps = np.column_stack((v * dt * np.cos(mid), v * dt * np.sin(mid)))
    return np.vstack(([0.0, 0.0], np.cumsum(steps, axis=0)))


def _path_positions(v: float, w: float, w_now: float | None, config: GuardConfig,
                    times: NDArray[np.float64]) -> NDArray[np.float64]:
    """The positions the guard checks: the commanded arc, or with the base's ω lag (w_now
    known and angular_accel > 0) the path the base really drives."""
    if w_now is None or config.angular_accel <= 0.0 or abs(w - w_now) < 1e-9:
        return arc_positions(v, w, times)
    return ramped_arc_positions(v, w, w_now, config.angular_accel, times)


def guard_velocity(v: float, w: float, points: Points, config: GuardConfig | None = None,
                   w_now: float | None = None) -> float:
    """The moving velocity the guard lets through for the command (v, ω) and the scan `points`
    (base frame, from scan_points). ω is never changed. Returns v' with |v'| <= |v|.

    `w_now`: the ω the base is turning at (the last command sent); None checks the commanded
    arc as if the base reached ω at once."""
    config = config or GuardConfig()
    if not config.enabled or v == 0.0:
        return float(v)
    if v < 0.0 and not config.allow_reverse:
        return 0.0
    return _arc_speed(v, w, _near_points(v, points, config), config, w_now)


def _near_points(v: float, points: Points, config: GuardConfig) -> Points:
    """The returns an arc at speed v can reach within the horizon (the rest cannot block it)."""
    if len(points) == 0:
        return points
    reach = abs(v) * config.horizon + config.radius + config.margin
    return points[np.hypot(points[:, 0], points[:, 1]) < reach]


def _arc_speed(v: float, w: float, near: Points, config: GuardConfig,
               w_now: float | None) -> float:
    """guard_velocity's v' for a moving command, given the returns _near_points kept."""
    if len(near) == 0:
        return float(v)
    reach = config.radius + config.margin
    steps = max(1, int(math.ceil(config.horizon / config.resolution)))
    times = np.linspace(0.0, config.horizon, steps + 1)
    positions = _path_positions(v, w, w_now, config, times)
    clearance = np.min(np.hypot(positions[:, None, 0] - near[None, :, 0],
                                positions[:, None, 1] - near[None, :, 1]), axis=1)
    if clearance[0] < reach:
        # already inside the margin: only an arc that comes no closer (1 mm for the scan's
        # discretisation) is allowed, e.g. along a wall or away from it
        return float(v) if clearance[1:].min() >= clearance[0] - 1e-3 else 0.0
    blocked = np.flatnonzero(clearance < reach)
    if len(blocked) == 0:
        return float(v)
    free_path = abs(v) * times[blocked[0] - 1]
    return math.copysign(min(abs(v), free_path / config.horizon), v)


def steer_around(v: float, w: float, points: Points, blocked_below: float,
                 config: GuardConfig | None = None,
                 w_now: float | None = None) -> tuple[float, float]:
    """Beyond the seed: the command (v', ω') the guard sends for (v, ω). As guard_velocity, with
    ω kept, unless the guard would stop a robot the network wants to move (guarded |v| below
    `blocked_below`, the slowest real motion, while |v| is not); then, with `steer` on:

    1. ω' is the rotating velocity nearest ω, on a grid of `steer_step` within ±`steer_range`,
       whose arc the guard lets through at `steer_speed` (or |v| if slower); v' is the guarded
       speed on that arc.
    2. If no arc is usable the robot turns in place (v' = 0): at the network's ω if that is
       already `steer_turn` or faster (a turn-around), else at `steer_turn` to the network's
       side, or, if the network barely turns (|ω| < `steer_step`), away from the nearest return
       ahead. A turn in place cannot touch a wall, and the next step tries the arcs again.

    `w_now` as in guard_velocity."""
    config = config or GuardConfig()
    guarded = guard_velocity(v, w, points, config, w_now)
    if not config.steer or abs(guarded) >= blocked_below or abs(v) < blocked_below:
        return guarded, float(w)
    steered = _nearest_free_arc(v, w, points, config, w_now)
    if steered is not None:
        return steered
    return _turn_in_place(guarded, w, points, config)


def _nearest_free_arc(v: float, w: float, points: Points, config: GuardConfig,
                      w_now: float | None) -> tuple[float, float] | None:
    """(v', ω') on the ω grid nearest ω (ties: further to ω's side) that the guard lets through
    at the usable speed, or None. The returns in reach depend on v only: selected once."""
    if v < 0.0 and not config.allow_reverse:
        return None
    near = _near_points(v, points, config)
    usable = min(abs(v), config.steer_speed)
    count = int(round(config.steer_range / config.steer_step))
    grid = config.steer_step * np.arange(-count, count + 1)
    side = math.copysign(1.0, w)
    for candidate in sorted(grid, key=lambda c: (abs(c - w), -c * side)):
        if abs(candidate - w) < 1e-9:
            continue
        speed = _arc_speed(v, float(candidate), near, config, w_now)
        if abs(speed) >= usable:
            return speed, float(candidate)
    return None


def _turn_in_place(guarded: float, w: float, points: Points,
                   config: GuardConfig) -> tuple[float, float]:
    """Step 2 of steer_around: (v', ω') when no arc is usable."""
    if abs(w) >= config.steer_turn:
        return guarded, float(w)
    if abs(w) >= config.steer_step:
        return 0.0, math.copysign(config.steer_turn, w)
    ahead = points[points[:, 0] > 0.0] if len(points) else points
    if len(ahead) == 0:
        return guarded, float(w)
    nearest = ahead[np.argmin(np.hypot(ahead[:, 0], ahead[:, 1]))]
    return 0.0, -math.copysign(config.steer_turn, nearest[1])


# what the guard did to a command (guard_action), as the follower counts them
GUARD_ACTIONS = ("slowed", "held", "steered", "turned")


def guard_action(v: float, w: float, sent_v: float, sent_w: float) -> str | None:
    """What the guard (with the follower's v_move stop) did to the command (v, ω) it sent as
    (sent_v, sent_w): "steered" to another ω, "turned" in place, "held" still (ω kept),
    "slowed", or None (passed unchanged)."""
    if sent_w != w:
        return "steered" if sent_v else "turned"
    if not sent_v:
        return "held"
    return "slowed" if abs(sent_v) < abs(v) else None


def format_guard_actions(counts: Mapping[str, int]) -> str:
    """{action: count} (DirectionFollower.guard_actions) -> "slowed N, held N, steered N,
    turned N", the node's diagnostics value."""
    return ", ".join(f"{action} {counts.get(action, 0)}" for action in GUARD_ACTIONS)
