"""Route oracle: where a person following a basic instruction (Table 3.1-1) would stop, computed
from an occupancy grid alone (any map_server floor, seen or unseen).

Method ("corridor walk"): from the start pose the oracle finds the corridor axis, walks along the
corridor centre line to the wall ahead and probes the free space to both sides with rays marched
on the distance field. Side openings at least `min_branch_width` wide that lead on for
`min_branch_depth` are corridor branches; narrower ones (doors) are side openings. Branches
whose spans along the walk overlap form one corner (a crossroad is one corner with both sides);
the corner the walk runs into is the corner at the end. The goal rule of a class follows its
entry in semantic_nav.instruction_classes (motion, side, at; docs/semantic_nav/oracle/):

  1  straight: end of the corridor, `stop_margin` before the wall ahead (n/a if already there)
  2/3  turn, at None: first corner ahead (or at the start: "immediately") with a branch on
       that side
  4  back: turn around on the spot (start position, heading reversed)
  5-8  turn at "second" / "third": the 2nd / 3rd corner counted over both sides must have a
       branch on that side
  9/10  turn at "end": the corner at the end must have a branch on that side
A turn goal lies on the branch centre line, `turn_exit_distance` beyond the branch mouth, facing
along the branch. Poses are (x [m], y [m], yaw [rad]) in the map frame.
"""
import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from semantic_nav.instruction_classes import (BACK, BY_ID, CLASS_IDS, COUNT_CORNERS, COUNT_SIDE,
                                              COUNTINGS, STRAIGHT, TURN, get)


class OracleError(ValueError):
    """A start pose or map the oracle cannot work with; the message says why."""


@dataclass
class OracleConfig:
    """Geometry of "a corridor" and of where a person stops."""

    robot_radius: float = 0.3        # start must have this clearance [m]
    step: float = 0.05               # spacing of the probes along the walk [m]
    axis_search: float = 35.0        # search the corridor axis within ± this of the heading [deg]
    max_half_width: float = 2.5      # a wall farther than this on both sides: no corridor [m]
    open_margin: float = 0.5         # side open if free beyond the wall line by this much [m]
    side_probe: float = 6.0          # length of the side rays [m]
    min_branch_width: float = 1.3    # narrower openings are doors, not corridor branches [m]
    min_door_width: float = 0.5      # narrower gaps are ignored [m]
    min_branch_depth: float = 1.5    # a branch must lead on this far from the wall line [m]
    stop_margin: float = 1.0         # a person stops this far before the wall ahead [m]
    turn_exit_distance: float = 1.0  # turn goal: this far beyond the branch mouth [m]
    behind: float = 3.0              # also probe this far behind the start [m]
    goal_radius: float = 0.75        # goal region radius [m]
    goal_heading_tolerance: float = 45.0  # goal region heading tolerance [deg]


@dataclass
class Opening:
    """An opening in one side wall of the walked corridor."""

    side: str          # "left" or "right"
    start: float       # first and last probe position along the walk [m]
    end: float
    depth: float       # free distance through its middle, from the centre line [m]
    is_branch: bool    # corridor branch (else a door / side opening)

    @property
    def centre(self):
        return 0.5 * (self.start + self.end)

    @property
    def width(self):
        return self.end - self.start


@dataclass
class Corner:
    """Overlapping branches on the two sides: an L corner, a T-junction or a crossroad."""

    branches: dict = field(default_factory=dict)   # side -> Opening
    at_end: bool = False


@dataclass
class CorridorWalk:
    """What the oracle saw walking from the start along the corridor."""

    origin: np.ndarray      # start projected onto the corridor centre line (x, y) [m]
    axis: float             # walking direction [rad]
    half_width: float       # median distance of the centre line to the nearer wall [m]
    front: float            # free distance ahead of the origin along the axis [m]
    openings: list          # every Opening (branches and doors)
    corners: list           # Corner, in walking order

    def point(self, s):
        return self.origin + s * np.array([math.cos(self.axis), math.sin(self.axis)])

    def frame(self, xy):
        """(x, y) -> (along, lateral) [m]: distance along the walk from the origin and offset
        from its centre line, positive to the left."""
        offset = np.asarray(xy, float)[:2] - self.origin
        c, s = math.cos(self.axis), math.sin(self.axis)
        return float(c * offset[0] + s * offset[1]), float(c * offset[1] - s * offset[0])


@dataclass
class Goal:
    """Where the person stops: a disc round (x, y) and a heading with a tolerance."""

    pose: tuple             # (x, y, yaw)
    radius: float           # [m]
    heading_tolerance: float  # [rad]

    def contains(self, x, y, yaw):
        dyaw = math.atan2(math.sin(yaw - self.pose[2]), math.cos(yaw - self.pose[2]))
        return (math.hypot(x - self.pose[0], y - self.pose[1]) <= self.radius
                and abs(dyaw) <= self.heading_tolerance)


class DistanceField:
    """Free-space clearance of a grid (metres to the nearest obstacle) and rays marched on it."""

    def __init__(self, grid):
        free = (~grid.occupied_mask()).astype(np.uint8)
        if not free.any():
            raise OracleError("map has no free cell")
        padded = np.pad(free, 1)           # the map border is a wall
        dist = cv2.distanceTransform(padded, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        self.clearance = dist[1:-1, 1:-1] * grid.resolution
        self.grid = grid
        # plain floats for `at`, which the ray march calls millions of times on single points
        self._x0, self._y0 = float(grid.origin[0]), float(grid.origin[1])
        self._resolution, self._rows, self._cols = float(grid.resolution), grid.height, grid.width

    def at(self, x, y):
        """Clearance [m] at a map-frame point; 0 outside the grid (OccupancyGrid.world_to_cell's
        cell, computed on scalars)."""
        col = math.floor((x - self._x0) / self._resolution)
        row = math.floor((y - self._y0) / self._resolution)
        if not (0 <= row < self._rows and 0 <= col < self._cols):
            return 0.0
        return float(self.clearance[row, col])

    def cast(self, x, y, angle, max_range):
        """Free distance from (x, y) along `angle`, at most max_range [m] (sphere tracing)."""
        return self._march(x, y, math.cos(angle), math.sin(angle), 0.0, max_range)

    def _march(self, x, y, dx, dy, t, max_range):
        """The sphere tracing of `cast` along (dx, dy), from `t` [m] along the ray on."""
        floor_step = 0.5 * self.grid.resolution
        while t < max_range:
            c = self.at(x + t * dx, y + t * dy)
            if c <= 0.0:
                return t
            t += max(c - 0.5 * self.grid.resolution, floor_step)
        return max_range

    def cast_many(self, xs, ys, angles, max_range, few=48):
        """`cast` of many rays at once -> array of their free distances, bit for bit those of
        `cast`: the same float64 steps, taken for every ray still marching together (a walk
        casts hundreds of rays; one by one they were most of the oracle's time). The last
        `few` rays still marching (along a wall, in short steps) finish one by one."""
        xs, ys, angles = (np.ravel(a).astype(float) for a in np.broadcast_arrays(xs, ys, angles))
        # math's cos and sin, not numpy's: their last bit may differ
        dx = np.array([math.cos(a) for a in angles.tolist()], dtype=float)
        dy = np.array([math.sin(a) for a in angles.tolist()], dtype=float)
        half = 0.5 * self.grid.resolution        # cast's floor step and clearance margin
        t = np.zeros(angles.size)
        free = np.full(angles.size, float(max_range))
        live = np.flatnonzero(t < max_range)
        while live.size > few:
            along = t[live]
            cols = np.floor((xs[live] + along * dx[live] - self._x0) / self._resolution)
            rows = np.floor((ys[live] + along * dy[live] - self._y0) / self._resolution)
            inside = (rows >= 0) & (rows < self._rows) & (cols >= 0) & (cols < self._cols)
            c = np.zeros(live.size)
            c[inside] = self.clearance[rows[inside].astype(np.intp), cols[inside].astype(np.intp)]
            hit = c <= 0.0
            free[live[hit]] = along[hit]
            along = along + np.maximum(c - half, half)
            t[live] = along
            live = live[~hit & (along < max_range)]
        for i in live.tolist():
            free[i] = self._march(float(xs[i]), float(ys[i]), float(dx[i]), float(dy[i]),
                                  float(t[i]), max_range)
        return free

    def cast_wide(self, x, y, angle, max_range, half_width):
        """Free distance of a strip 2 * half_width wide (three parallel rays): a door narrower
        than the strip ends a walk as a wall does, a corridor does not."""
        nx, ny = -math.sin(angle), math.cos(angle)
        return min(self.cast(x + k * half_width * nx, y + k * half_width * ny, angle, max_range)
                   for k in (-1.0, 0.0, 1.0))


def _theil_sen_slope(s, d):
    """Median of the pairwise slopes: robust to a few rays through doors."""
    i, j = np.triu_indices(len(s), k=1)
    return float(np.median((d[j] - d[i]) / (s[j] - s[i])))


def _tilt(field, origin, angle, config):
    """Angle between `angle` and the side walls from how the side distances change along it
    (left distances shrink by tan δ per metre when turned δ towards the left wall), or None."""
    u = np.array([math.cos(angle), math.sin(angle)])
    estimates = []
    for sign in (1.0, -1.0):
        s_d = []
        for s in np.arange(-1.0, 3.01, 0.25):
            p = origin + s * u
            if field.at(*p) > 0.0:
                d = field.cast(*p, angle + sign * math.pi / 2, config.max_half_width)
                if d < config.max_half_width:
                    s_d.append((s, d))
        if len(s_d) >= 5:
            s_values, d_values = np.array(s_d).T
            estimates.append(-sign * math.atan(_theil_sen_slope(s_values, d_values)))
    return float(np.mean(estimates)) if estimates else None


def corridor_axis(field, x, y, yaw, config):
    """Axis of the corridor the start pose faces: the longest free ray within ±axis_search of
    the heading (nearest to it among the near-longest), refined along the side walls."""
    angles = yaw + np.radians(np.arange(-config.axis_search, config.axis_search + 0.5, 1.0))
    lengths = field.cast_many(x, y, angles, 100.0)
    near_best = np.flatnonzero(lengths >= 0.97 * lengths.max())
    coarse = float(angles[near_best[np.argmin(np.abs(angles[near_best] - yaw))]])
    axis = coarse
    for _ in range(3):
        tilt = _tilt(field, np.array([x, y]), axis, config)
        if tilt is None:
            break
        axis -= tilt
        if abs(tilt) < math.radians(0.1):
            break
    return axis if abs(axis - coarse) <= math.radians(config.axis_search) else coarse


def true_runs(mask):
    """Index ranges [(first, last)] of consecutive True values."""
    padded = np.concatenate([[False], mask, [False]]).astype(int)
    edges = np.flatnonzero(np.diff(padded))
    return list(zip(edges[::2], edges[1::2] - 1))


def find_openings(field, walk, positions, side_distances, config):
    """Openings in each side wall from the side-ray lengths along the walk."""
    openings = []
    for side, sign in (("left", 1.0), ("right", -1.0)):
        distances = side_distances[side]
        for first, last in true_runs(distances > walk.half_width + config.open_margin):
            width = positions[last] - positions[first] + config.step
            if width < config.min_door_width:
                continue
            centre = walk.point(0.5 * (positions[first] + positions[last]))
            depth = field.cast(centre[0], centre[1], walk.axis + sign * math.pi / 2, 50.0)
            branch = (width >= config.min_branch_width
                      and depth >= walk.half_width + config.min_branch_depth)
            openings.append(Opening(side, positions[first], positions[last], depth, branch))
    return openings


def group_corners(openings, last_position, config):
    """Corridor branches whose spans overlap -> one Corner each, in walking order."""
    corners = []
    for opening in sorted((o for o in openings if o.is_branch), key=lambda o: o.start):
        previous = corners[-1] if corners else None
        if previous and any(opening.start <= b.end and b.start <= opening.end
                            for b in previous.branches.values()) \
                and opening.side not in previous.branches:
            previous.branches[opening.side] = opening
        else:
            corners.append(Corner({opening.side: opening}))
    for corner in corners:
        corner.at_end = any(b.end >= last_position - 1.5 * config.step
                            for b in corner.branches.values())
    return corners


def _centre_offset(field, xy, axis, config):
    """Sideways shift onto the centre line: median over the metre before and after the start
    of half the difference of the side distances, where both walls are seen."""
    u = np.array([math.cos(axis), math.sin(axis)])
    normal = np.array([-u[1], u[0]])
    shifts = []
    for s in np.arange(-1.0, 1.01, 0.1):
        p = np.asarray(xy) + s * u
        if field.at(*p) <= 0.0:
            continue
        left = field.cast(*p, axis + math.pi / 2, config.max_half_width)
        right = field.cast(*p, axis - math.pi / 2, config.max_half_width)
        if max(left, right) < config.max_half_width:
            shifts.append(0.5 * (left - right))
    return float(np.median(shifts)) * normal if shifts else np.zeros(2)


def walk_corridor(field, start, config):
    """Walk from `start` = (x, y, yaw) along its corridor to the wall ahead -> CorridorWalk."""
    x, y, yaw = (float(v) for v in start)
    if field.at(x, y) < config.robot_radius:
        raise OracleError(f"start ({x:.2f}, {y:.2f}) is not free space with "
                          f"{config.robot_radius} m clearance")
    axis = corridor_axis(field, x, y, yaw, config)
    left = field.cast(x, y, axis + math.pi / 2, config.side_probe)
    right = field.cast(x, y, axis - math.pi / 2, config.side_probe)
    if min(left, right) > config.max_half_width:
        raise OracleError(f"no corridor at ({x:.2f}, {y:.2f}): no wall within "
                          f"{config.max_half_width} m on either side")
    origin = np.array([x, y]) + _centre_offset(field, (x, y), axis, config)
    # the strip must fit the corridor itself (narrow household alleys) but not a door
    strip = min(0.5 * config.min_branch_width, 0.8 * min(left, right)) - config.step
    walk = CorridorWalk(origin, axis, 0.0, field.cast_wide(*origin, axis, 200.0, strip), [], [])
    back = field.cast_wide(*origin, axis + math.pi, config.behind, strip)
    positions = np.arange(-math.floor(back / config.step) + 1,
                          math.floor(walk.front / config.step)) * config.step
    if positions.size < 2:
        raise OracleError(f"no room to walk from ({x:.2f}, {y:.2f})")
    # walk.point of every position (the same arithmetic, on all of them at once)
    points = walk.origin + positions[:, None] * np.array([math.cos(axis), math.sin(axis)])
    sides = {name: field.cast_many(points[:, 0], points[:, 1], axis + sign * math.pi / 2,
                                   config.side_probe)
             for name, sign in (("left", 1.0), ("right", -1.0))}
    nearer = np.minimum(sides["left"], sides["right"])
    walled = nearer[np.maximum(sides["left"], sides["right"]) <= config.max_half_width]
    walk.half_width = float(np.median(walled if walled.size else nearer))
    walk.openings = find_openings(field, walk, positions, sides, config)
    walk.corners = [c for c in group_corners(walk.openings, positions[-1], config)
                    if max(b.end for b in c.branches.values()) >= 0.0]
    return walk


def _turn_goal(walk, branch, config):
    """On the branch centre line, turn_exit_distance past its mouth, facing along the branch."""
    sign = 1.0 if branch.side == "left" else -1.0
    heading = walk.axis + sign * math.pi / 2
    junction = walk.point(branch.centre)
    reach = min(walk.half_width + config.turn_exit_distance, branch.depth - config.stop_margin)
    reach = max(reach, walk.half_width)
    xy = junction + reach * np.array([math.cos(heading), math.sin(heading)])
    return (float(xy[0]), float(xy[1]), math.remainder(heading, 2 * math.pi))


def goal_branch(walk, label, counting=COUNT_CORNERS):
    """The branch a turn class (2, 3, 5-10) turns into, or None when there is none. With
    `counting` COUNT_SIDE, classes 5-8 count the branches on their side only ("the second
    right": the second right-hand branch, nth_branch_on_side)."""
    cls = get(label)
    if cls.motion != TURN:
        raise OracleError(f"instruction class {label} is not a turn")
    if counting not in COUNTINGS:
        raise OracleError(f"unknown counting {counting!r} (one of {', '.join(COUNTINGS)})")
    if counting == COUNT_SIDE and cls.corner is not None:
        return nth_branch_on_side(walk, cls.side, cls.corner)
    if cls.at is None:
        return nth_branch_on_side(walk, cls.side, 1)
    if cls.at == "end":
        corner = walk.corners[-1] if walk.corners and walk.corners[-1].at_end else None
    else:
        corner = walk.corners[cls.corner - 1] if len(walk.corners) >= cls.corner else None
    return corner.branches.get(cls.side) if corner else None


def branches_on_side(walk, side):
    """The branches on `side` of the walk, in walking order."""
    return [c.branches[side] for c in walk.corners if side in c.branches]


def nth_branch_on_side(walk, side, nth):
    """The `nth` branch on `side`, counting only the corners with a branch there, or None."""
    branches = branches_on_side(walk, side)
    return branches[nth - 1] if len(branches) >= nth else None


def one_side_branch(walk, label):
    """Classes 5-8 counted the wrong way, over the corners with a branch on the turning side
    only: the branch that count reaches, or None."""
    cls = get(label)
    return nth_branch_on_side(walk, cls.side, cls.corner)


def counting_matters(walk, label):
    """True when class `label` (5-8) applies here and counting the corners over both sides
    (the oracle's rule) reaches another branch than counting one side only: the starts that
    teach a network to count every corner, not only those on its turning side (beyond the
    seed; a network trained without enough of them turns at the Nth opening on its side)."""
    cls = BY_ID.get(label)
    if cls is None or cls.corner is None:
        return False
    branch = goal_branch(walk, label)
    return branch is not None and branch is not one_side_branch(walk, label)


def goal_pose(walk, label, config, counting=COUNT_CORNERS):
    """Table 3.1-1 class -> goal pose (x, y, yaw), or None when not applicable here
    (`counting`: goal_branch's)."""
    motion = get(label).motion
    if motion == STRAIGHT:
        s_end = walk.front - config.stop_margin
        if s_end < config.stop_margin:
            return None
        xy = walk.point(s_end)
        return (float(xy[0]), float(xy[1]), math.remainder(walk.axis, 2 * math.pi))
    if motion == BACK:
        xy = walk.origin
        return (float(xy[0]), float(xy[1]), math.remainder(walk.axis + math.pi, 2 * math.pi))
    branch = goal_branch(walk, label, counting)
    return None if branch is None else _turn_goal(walk, branch, config)


class RouteOracle:
    """Goals of the instruction classes on one occupancy grid (a map_server floor)."""

    def __init__(self, grid, config=None):
        self.config = config or OracleConfig()
        self.field = DistanceField(grid)

    def walk(self, start):
        return walk_corridor(self.field, start, self.config)

    def goal(self, start, label, walk=None, counting=COUNT_CORNERS):
        """Goal region of class `label` from `start`, or None ("not applicable here");
        `counting`: COUNT_SIDE for "the second right" (goal_branch)."""
        if label not in BY_ID:
            raise OracleError(f"unknown instruction class {label!r} "
                              f"({CLASS_IDS[0]}..{CLASS_IDS[-1]})")
        pose = goal_pose(walk or self.walk(start), label, self.config, counting)
        if pose is None:
            return None
        return Goal(pose, self.config.goal_radius,
                    math.radians(self.config.goal_heading_tolerance))

    def goals(self, start):
        """{class: Goal or None} for every instruction class from one start."""
        walk = self.walk(start)
        return {label: self.goal(start, label, walk) for label in CLASS_IDS}
