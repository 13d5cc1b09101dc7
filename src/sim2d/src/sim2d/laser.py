"""Laser range finders: models from config/lasers/*.yaml and scans with noise and dropouts."""
import math
from collections.abc import Callable, Sequence
from dataclasses import astuple, dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import yaml

from sim2d.raycast import GridGeometry, RangeTable, ray_march

NOISE_POOL = 1 << 18   # standard normals drawn once; each scan reads a slice at a random offset
OFFSET_BLOCK = 4096    # random pool offsets drawn at once
Circles = Sequence[Sequence[float]] | np.ndarray   # [(x, y, r)] [m]
Boxes = Sequence[Sequence[float]] | np.ndarray     # [(x0, y0, x1, y1)] [m]


class LaserModelError(ValueError):
    """A laser model file or name that cannot be used."""


@dataclass
class LaserModel:
    """One laser range finder model (sensor_msgs/LaserScan conventions)."""

    name: str
    angle_min: float            # [rad]
    angle_max: float            # [rad]
    angle_increment: float      # [rad]
    range_min: float            # [m]
    range_max: float            # [m]
    scan_time: float            # [s] time per scan = publication period
    noise_std: float = 0.0      # [m] range noise floor (1 sigma)
    noise_fraction: float = 0.0  # [-] range-proportional noise (1 sigma / range)
    dropout_probability: float = 0.0  # [-] chance a beam returns nothing
    num_beams: int = 0          # [-] 0: derived from the angle span

    def __post_init__(self) -> None:
        if self.num_beams <= 0:
            span = (self.angle_max - self.angle_min) / self.angle_increment
            self.num_beams = int(round(span)) + 1
        self.angle_max = self.angle_min + (self.num_beams - 1) * self.angle_increment

    def beam_angles(self) -> npt.NDArray[np.float64]:
        """Beam directions [rad] in the laser frame."""
        return self.angle_min + np.arange(self.num_beams) * self.angle_increment


LASER_FIELDS = ("name", "angle_min", "angle_max", "angle_increment", "range_min", "range_max",
                "scan_time")


def load_laser_model(path: str | Path) -> LaserModel:
    """Read one config/lasers/<model>.yaml; LaserModelError names the file and the problem."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise LaserModelError(f"{path}: cannot read laser model: {error}") from error
    if not isinstance(data, dict):
        raise LaserModelError(f"{path}: laser model must be a mapping")
    missing = [key for key in LASER_FIELDS if key not in data]
    if missing:
        raise LaserModelError(f"{path}: missing key(s) {', '.join(missing)}")
    unknown = set(data) - set(LaserModel.__dataclass_fields__)
    if unknown:
        raise LaserModelError(f"{path}: unknown key(s) {', '.join(sorted(unknown))}")
    model = LaserModel(**data)
    if not (model.angle_increment > 0 and 0 <= model.range_min < model.range_max
            and model.scan_time > 0):
        raise LaserModelError(f"{path}: need angle_increment > 0, 0 <= range_min < range_max "
                              f"and scan_time > 0")
    return model


def find_laser_model(name: str, laser_dir: str | Path) -> LaserModel:
    """The model called `name` in laser_dir; the error lists the models that exist."""
    path = Path(laser_dir) / f"{name}.yaml"
    if not path.is_file():
        known = sorted(p.stem for p in Path(laser_dir).glob("*.yaml"))
        raise LaserModelError(f"unknown laser model {name!r} (known in {laser_dir}: "
                              f"{', '.join(known) or 'none'})")
    return load_laser_model(path)


def circle_ranges(ox: float, oy: float, angles: np.ndarray, circles: Circles) -> np.ndarray:
    """Ranges [m] along each ray to the nearest of `circles` [(x, y, r)], inf if none is hit."""
    if len(circles) == 0:
        return np.full(np.shape(angles), np.inf)
    c = np.asarray(circles, dtype=float)
    dx, dy = c[:, 0:1] - ox, c[:, 1:2] - oy
    cos, sin = np.cos(angles)[None, :], np.sin(angles)[None, :]
    along = dx * cos + dy * sin
    perp2 = dx * dx + dy * dy - along * along
    half = np.sqrt(np.maximum(c[:, 2:3] ** 2 - perp2, 0.0))
    t = along - half
    hit = (perp2 <= c[:, 2:3] ** 2) & (t > 0)
    return np.where(hit, t, np.inf).min(axis=0)


def beam_windows(bearings: np.ndarray, halves: np.ndarray, angle_min: float, increment: float,
                 num_beams: int) -> tuple[np.ndarray, np.ndarray]:
    """Per circle, the beams of a fan (beam i at angle_min + i * increment) that can reach it:
    its bearing +- its angular half-width, one beam of margin each side (the exact test decides
    the tangent beams). -> (circle index, beam index) pairs as two flat int arrays. A window
    across the fan's +-pi seam is split in two, so a 360-degree laser loses no beam."""
    two_pi = 2.0 * math.pi
    start = np.mod(bearings - halves - angle_min, two_pi) / increment   # beams from beam 0
    end = start + (2.0 * halves) / increment
    lows, highs = np.ceil(start) - 1.0, np.floor(end) + 1.0
    owners = np.arange(len(bearings))
    # the part past 2 pi wraps to the fan's start (only a full circle has beams there)
    wrap_highs = np.floor(end - two_pi / increment) + 1.0
    if len(wrap_highs) and wrap_highs.max() >= 0.0:
        lows = np.concatenate([lows, np.zeros_like(lows)])
        highs = np.concatenate([highs, wrap_highs])
        owners = np.concatenate([owners, owners])
    lows = np.maximum(lows, 0.0).astype(np.int64)
    highs = np.minimum(highs, num_beams - 1.0).astype(np.int64)
    keep = highs >= lows
    if not keep.all():
        lows, highs, owners = lows[keep], highs[keep], owners[keep]
    if not len(lows):
        return owners, lows
    counts = highs - lows + 1
    # the beams as a running sum: +1 inside a window, a jump from one window's last beam to
    # the next one's first
    steps = np.ones(int(counts.sum()), dtype=np.int64)
    steps[0] = lows[0]
    steps[np.cumsum(counts[:-1])] = lows[1:] - highs[:-1]
    return np.repeat(owners, counts), np.cumsum(steps)


def overlay_circles(ranges: np.ndarray, lx: float, ly: float, lyaw: float, circles: Circles,
                    cos_beam: np.ndarray, sin_beam: np.ndarray, angle_min: float,
                    increment: float, reach: float = math.inf) -> np.ndarray:
    """`ranges` with circles [(x, y, r)] overlaid, each cast only on the beams of its angular
    window (beam_windows), in the laser frame with the beams' precomputed cos / sin: the same
    hits as circle_ranges at a cost that grows with the beams the circles cover, not with
    circles x beams. A laser inside a circle sees none of it (as circle_ranges); a circle
    wholly beyond `reach` [m] is skipped (its hits would be out of the laser's range)."""
    c = np.asarray(circles, dtype=float)
    dx, dy = c[:, 0] - lx, c[:, 1] - ly
    d2, r2 = dx * dx + dy * dy, c[:, 2] * c[:, 2]
    seen = (d2 > r2) & (d2 < (reach + c[:, 2]) ** 2)
    if not seen.any():
        return ranges
    dx, dy, d2, r2 = dx[seen], dy[seen], d2[seen], r2[seen]
    cy, sy = math.cos(lyaw), math.sin(lyaw)
    circle, beam, t = window_hits(cy * dx + sy * dy, -sy * dx + cy * dy, d2, r2, cos_beam,
                                  sin_beam, angle_min, increment, len(ranges))
    if not len(beam):
        return ranges
    out = np.array(ranges, dtype=float)
    np.minimum.at(out, beam, t)
    return out


def window_hits(fx: np.ndarray, fy: np.ndarray, d2: np.ndarray, r2: np.ndarray,
                cos_beam: np.ndarray, sin_beam: np.ndarray, angle_min: float, increment: float,
                num_beams: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The beams that hit circles seen from a laser: circles at (fx, fy) in the laser frame,
    squared distance d2 and squared radius r2 (arrays, one per circle), each cast on the beams of
    its angular window (beam_windows) -> (circle index, beam index, range) per hit."""
    halves = np.arcsin(np.sqrt(r2 / d2))
    circle, beam = beam_windows(np.arctan2(fy, fx), halves, angle_min, increment, num_beams)
    if not len(beam):
        return circle, beam, np.zeros(0)
    along = fx[circle] * cos_beam[beam] + fy[circle] * sin_beam[beam]
    perp2 = d2[circle] - along * along
    t = along - np.sqrt(np.maximum(r2[circle] - perp2, 0.0))
    hit = (perp2 <= r2[circle]) & (t > 0)
    return circle[hit], beam[hit], t[hit]


def box_ranges(ox: float, oy: float, angles: np.ndarray, boxes: Boxes) -> np.ndarray:
    """Ranges [m] along each ray to the nearest axis-aligned box [(x0, y0, x1, y1)] (slab
    method, exact), inf if none is hit; 0 for a ray starting inside a box."""
    if len(boxes) == 0:
        return np.full(np.shape(angles), np.inf)
    b = np.asarray(boxes, dtype=float)
    cos, sin = np.cos(angles)[None, :], np.sin(angles)[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        tx0, tx1 = (b[:, 0:1] - ox) / cos, (b[:, 2:3] - ox) / cos
        ty0, ty1 = (b[:, 1:2] - oy) / sin, (b[:, 3:4] - oy) / sin
    # a ray parallel to an axis: inside the slab for all t, or never
    inside_x = (b[:, 0:1] <= ox) & (ox <= b[:, 2:3])
    inside_y = (b[:, 1:2] <= oy) & (oy <= b[:, 3:4])
    parallel_x, parallel_y = np.abs(cos) < 1e-12, np.abs(sin) < 1e-12
    enter_x = np.where(parallel_x, np.where(inside_x, -np.inf, np.inf), np.minimum(tx0, tx1))
    leave_x = np.where(parallel_x, np.where(inside_x, np.inf, -np.inf), np.maximum(tx0, tx1))
    enter_y = np.where(parallel_y, np.where(inside_y, -np.inf, np.inf), np.minimum(ty0, ty1))
    leave_y = np.where(parallel_y, np.where(inside_y, np.inf, -np.inf), np.maximum(ty0, ty1))
    enter, leave = np.maximum(enter_x, enter_y), np.minimum(leave_x, leave_y)
    hit = (enter <= leave) & (leave > 0)
    return np.where(hit, np.maximum(enter, 0.0), np.inf).min(axis=0)


class LaserSensor:
    """A laser of a given model mounted on a robot; `scan(pose)` returns noisy ranges."""

    def __init__(self, model: LaserModel, mount: Sequence[float], geometry: GridGeometry,
                 table: RangeTable | None = None, seed: int = 0) -> None:
        self.model = model
        self.mount = tuple(float(v) for v in mount)   # (x, y, yaw) in base_link [m, m, rad]
        self.geometry = geometry
        self.table = table                            # RangeTable or None (ray marching)
        self.rng = np.random.default_rng(seed)
        self.angles = model.beam_angles()
        self._cos, self._sin = np.cos(self.angles), np.sin(self.angles)
        self.windowed = True     # circles cast on their angular window; False: on every beam
        self.model_key = astuple(model)   # lasers of one model scan together
        # circles farther than this are not cast: beyond range_max with room for the range
        # noise that could bring a hit back under it
        self._reach = 1.25 * model.range_max + 1.0
        # one pool per scan component, read at random offsets: N(0, 1) range noise, and the
        # same noise pre-scaled by noise_std with +inf where a beam drops out (one add per scan)
        normal = self.rng.standard_normal(NOISE_POOL + model.num_beams)
        dropped = self.rng.random(NOISE_POOL + model.num_beams) < model.dropout_probability
        self._pools = {"normal": normal.astype(np.float32),
                       "dropout": np.where(dropped, np.inf, 0.0).astype(np.float32),
                       "noise": np.where(dropped, np.inf,
                                         model.noise_std * normal).astype(np.float32)}
        self._offsets: list[int] = []
        self._next_offset = 0
        steps = model.angle_increment / (2.0 * np.pi / table.config.angle_bins) if table else 0.0
        self.fan_step = int(round(steps)) if table and abs(steps - round(steps)) < 1e-6 else 0

    def reseed(self, seed: int) -> None:
        """Restart the noise stream (e.g. per episode, so an episode's scans do not depend on
        the episodes run before it); the noise pools stay those of the construction seed."""
        self.rng = np.random.default_rng(seed)
        self._offsets, self._next_offset = [], 0

    def pose_in_map(self, pose: Sequence[float]) -> tuple[float, float, float]:
        x, y, yaw = pose
        mx, my, myaw = self.mount
        c, s = math.cos(yaw), math.sin(yaw)
        return x + c * mx - s * my, y + s * mx + c * my, yaw + myaw

    def true_ranges(self, pose: Sequence[float], circles: Circles = (),
                    boxes: Boxes = ()) -> np.ndarray:
        """Noise-free ranges [m] from the map, circular obstacles such as people and boxes such
        as closed doors (exact casts overlaid on the static map's table or ray march)."""
        lx, ly, lyaw = self.pose_in_map(pose)
        ranges: np.ndarray | None = None
        if self.fan_step and self.table is not None:   # a fan step implies a table
            ranges = self.table.cast_fan(lx, ly, lyaw + self.model.angle_min,
                                         self.model.num_beams, self.fan_step)
            if ranges is not None and not len(circles) and not len(boxes):
                return ranges
        world_angles = self.angles + lyaw
        if ranges is None and self.table is not None:
            ranges = self.table.cast(lx, ly, world_angles)
        if ranges is None:
            ranges = ray_march(self.geometry, lx, ly, world_angles, self.model.range_max)
        if len(circles) and not self.windowed:
            ranges = np.minimum(ranges, circle_ranges(lx, ly, world_angles, circles))
        elif len(circles):
            ranges = overlay_circles(ranges, lx, ly, lyaw, circles, self._cos, self._sin,
                                     self.model.angle_min, self.model.angle_increment,
                                     self._reach)
        if len(boxes):
            ranges = np.minimum(ranges, box_ranges(lx, ly, world_angles, boxes))
        return ranges

    def _pool_slice(self, pool: np.ndarray) -> np.ndarray:
        if self._next_offset == len(self._offsets):     # offsets drawn in bulk: cheaper per scan
            self._offsets = self.rng.integers(0, NOISE_POOL, OFFSET_BLOCK).tolist()
            self._next_offset = 0
        start = self._offsets[self._next_offset]
        self._next_offset += 1
        return pool[start:start + self.model.num_beams]

    def scan(self, pose: Sequence[float], circles: Circles = (), boxes: Boxes = ()) -> np.ndarray:
        """One scan [m]: Gaussian range noise, dropouts and out-of-range beams as +inf (REP 117)."""
        ranges = np.asarray(self.true_ranges(pose, circles, boxes), dtype=np.float32)
        return noisy_ranges(self.model, ranges, lambda pool: self._pool_slice(self._pools[pool]))


def noisy_ranges(model: LaserModel, ranges: np.ndarray,
                 draw: Callable[[str], np.ndarray]) -> np.ndarray:
    """Gaussian range noise, dropouts and out-of-range beams as +inf (REP 117) on float32 true
    ranges [m] of one scan or rows of scans; draw(pool) reads the noise pool "normal",
    "dropout" or "noise" (LaserSensor) in the shape of `ranges`. Returns a new array."""
    if model.noise_fraction > 0:
        within = np.minimum(ranges, np.float32(model.range_max))   # no inf * noise = NaN
        sigma = np.maximum(np.float32(model.noise_std), np.float32(model.noise_fraction) * within)
        ranges = ranges + sigma * draw("normal")
        ranges += draw("dropout")
    else:
        ranges = ranges + draw("noise")
    np.putmask(ranges, ranges > model.range_max, np.inf)   # half a boolean setitem's cost
    if ranges.min() < model.range_min:
        np.putmask(ranges, ranges < model.range_min, -np.inf)
    return ranges
