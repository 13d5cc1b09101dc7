"""Vectorised 2D ray casting on an occupancy grid.

Two casters share one geometry (occupied cells are squares of side `resolution`):

* `ray_march`: sphere tracing on a Euclidean distance transform, vectorised over all rays
  (no Python loop per beam); exact up to the final sub-cell refinement. Used for short-range,
  few-beam lasers, line-of-sight tests and to build the table below.
* `RangeTable`: a per-cell, per-angle lookup table for static maps (the LUT of rangelibc;
  Walsh & Karaman, ICRA 2018). A whole scan is then one gather from four table rows plus a
  bilinear blend, which is what makes real-time factors in the hundreds reachable in numpy.
"""
import hashlib
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, overload

import cv2
import numpy as np
import numpy.typing as npt

from floorplan.occupancy_map import OccupancyMap

TABLE_FORMAT = "faces-dda-v3"   # bump when the table contents change (invalidates caches)
SAFE_MARGIN = 1.5        # [cells] DT bound loss: point-to-cell-centre plus half a cell diagonal
MAX_ITERATIONS = 4000    # guard against pathological grazing rays
CLEARANCE_LOSS = np.sqrt(2.0)  # [cells] point-to-centre plus half the obstacle cell's diagonal


def distance_transform(occupied: np.ndarray) -> npt.NDArray[np.float32]:
    """Distance [cells] from every cell centre to the nearest occupied cell centre (0 inside)."""
    free = np.ascontiguousarray(~occupied, dtype=np.uint8)
    return cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE).astype(np.float32)


def _cell_entry(ox: np.ndarray, oy: np.ndarray, cos: np.ndarray, sin: np.ndarray,
                col: np.ndarray, row: np.ndarray, origin_x: float, origin_y: float,
                resolution: float) -> tuple[np.ndarray, np.ndarray]:
    """Range at which each ray enters its cell square (slab method), and whether it enters
    through a face parallel to x (a "y face", normal along y)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        x0 = origin_x + col * resolution
        y0 = origin_y + row * resolution
        tx = np.where(cos > 0, (x0 - ox) / cos, (x0 + resolution - ox) / cos)
        ty = np.where(sin > 0, (y0 - oy) / sin, (y0 + resolution - oy) / sin)
        tx = np.where(np.abs(cos) < 1e-12, -np.inf, tx)
        ty = np.where(np.abs(sin) < 1e-12, -np.inf, ty)
    return np.maximum(np.maximum(tx, ty), 0.0), ty > tx


@dataclass
class GridGeometry:
    """What a caster needs to know of a map: occupancy, distance transform and placement."""

    occupied: np.ndarray   # bool (H, W)
    dist: np.ndarray       # float32 (H, W) distance transform [cells]
    resolution: float      # [m/cell]
    origin_x: float        # [m] map-frame x of cell (0, 0)'s corner
    origin_y: float        # [m]

    @classmethod
    def from_map(cls, grid: OccupancyMap) -> "GridGeometry":
        if abs(grid.origin[2]) > 1e-9:
            raise ValueError(f"rotated map origins are not supported (yaw {grid.origin[2]})")
        occupied = grid.occupied_mask()
        return cls(occupied, distance_transform(occupied), float(grid.resolution),
                   float(grid.origin[0]), float(grid.origin[1]))

    def clearance_at(self, x: float, y: float) -> float:
        """Scalar clearance (see `clearance`), without numpy overhead."""
        col = math.floor((x - self.origin_x) / self.resolution)
        row = math.floor((y - self.origin_y) / self.resolution)
        if not (0 <= row < self.dist.shape[0] and 0 <= col < self.dist.shape[1]):
            return 0.0
        d = float(self.dist[row, col])
        return max(d - CLEARANCE_LOSS, 0.0) * self.resolution if d > 0 else 0.0

    def clearance(self, x: npt.ArrayLike, y: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Lower bound [m] of the free distance around map points (0 outside or in obstacles)."""
        col = np.floor((np.asarray(x, dtype=float) - self.origin_x) / self.resolution).astype(int)
        row = np.floor((np.asarray(y, dtype=float) - self.origin_y) / self.resolution).astype(int)
        h, w = self.dist.shape
        inside = (row >= 0) & (row < h) & (col >= 0) & (col < w)
        d = np.zeros(np.shape(col), dtype=float)
        d[inside] = self.dist[row[inside], col[inside]]
        return np.maximum(d - CLEARANCE_LOSS, 0.0) * self.resolution * (d > 0)


@overload
def ray_march(geometry: GridGeometry, ox: npt.ArrayLike, oy: npt.ArrayLike,
              angles: npt.ArrayLike, max_range: float,
              return_faces: Literal[False] = False) -> npt.NDArray[np.float64]: ...


@overload
def ray_march(geometry: GridGeometry, ox: npt.ArrayLike, oy: npt.ArrayLike,
              angles: npt.ArrayLike, max_range: float, return_faces: Literal[True]
              ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]: ...


def ray_march(geometry: GridGeometry, ox: npt.ArrayLike, oy: npt.ArrayLike,
              angles: npt.ArrayLike, max_range: float, return_faces: bool = False
              ) -> npt.NDArray[np.float64] | tuple[npt.NDArray[np.float64],
                                                   npt.NDArray[np.bool_]]:
    """Ranges [m] of rays from (ox, oy) at `angles` [rad] to the first occupied cell.

    Far from obstacles a ray jumps by the distance-transform bound (sphere tracing); within
    SAFE_MARGIN + 1 cells of one it steps exactly from cell boundary to cell boundary (DDA), so
    no cell is skipped; the hit range is the exact entry into the hit cell's square. All rays
    advance together (no Python loop per ray). Rays that leave the map or exceed max_range
    return inf. With return_faces, also a bool array: True where the ray entered through a y face.
    """
    angles = np.asarray(angles, dtype=float)
    ox = np.broadcast_to(np.asarray(ox, dtype=float), angles.shape).ravel()
    oy = np.broadcast_to(np.asarray(oy, dtype=float), angles.shape).ravel()
    cos, sin = np.cos(angles).ravel(), np.sin(angles).ravel()
    ranges = np.full(cos.shape, np.inf)
    faces = np.zeros(cos.shape, dtype=bool)
    res, (h, w) = geometry.resolution, geometry.dist.shape
    # ray origins in cell units relative to the grid corner; per-axis cell-crossing data
    gx, gy = (ox - geometry.origin_x) / res, (oy - geometry.origin_y) / res
    # 1/cos and 1/sin, 0 for an axis the ray does not move along: that axis is never crossed,
    # even from a start a rounding error below one of its cell boundaries
    with np.errstate(divide="ignore"):
        inv_c = np.where(np.abs(cos) > 1e-12, 1.0 / cos, 0.0)
        inv_s = np.where(np.abs(sin) > 1e-12, 1.0 / sin, 0.0)
    step_x, step_y = (inv_c > 0).astype(float), (inv_s > 0).astype(float)
    # working set, compacted whenever fewer than half of its rays are still live
    idx = np.arange(cos.size)
    wx, wy, wc, ws, ic, is_, sx, sy = gx, gy, cos, sin, inv_c, inv_s, step_x, step_y
    t = np.zeros(cos.size)                # [cells] along the ray
    live = np.ones(cos.size, dtype=bool)
    flat = geometry.dist.ravel()
    limit = max_range / res
    for _ in range(MAX_ITERATIONS):
        px, py = wx + t * wc, wy + t * ws
        col, row = np.floor(px), np.floor(py)
        inside = (row >= 0) & (row < h) & (col >= 0) & (col < w) & (t <= limit)
        cell = np.clip(row * w + col, 0, h * w - 1).astype(np.int64)
        d = np.where(inside, flat[cell], 0.0)
        hit = live & inside & (d == 0.0)
        if hit.any():
            entry, face = _cell_entry(wx[hit], wy[hit], wc[hit], ws[hit], col[hit], row[hit],
                                      0.0, 0.0, 1.0)
            ranges[idx[hit]], faces[idx[hit]] = entry * res, face
        live &= inside & ~hit
        count = int(np.count_nonzero(live))
        if count == 0:
            break
        # exact exit from the current cell (DDA) versus the distance-transform jump
        exit_t = np.minimum(np.where(ic != 0.0, (col + sx - wx) * ic, np.inf),
                            np.where(is_ != 0.0, (row + sy - wy) * is_, np.inf))
        t = np.maximum(t + (d - SAFE_MARGIN), exit_t + 1e-9)
        if count < live.size // 2:
            idx, wx, wy, wc, ws, ic, is_, sx, sy, t = (
                a[live] for a in (idx, wx, wy, wc, ws, ic, is_, sx, sy, t))
            live = np.ones(count, dtype=bool)
    ranges[ranges > max_range] = np.inf
    if return_faces:
        return ranges.reshape(angles.shape), faces.reshape(angles.shape)
    return ranges.reshape(angles.shape)


def segments_clear(geometry: GridGeometry, ox: float, oy: float, targets: npt.ArrayLike,
                   spacing: float = 0.5) -> npt.NDArray[np.bool_]:
    """True for each target (x, y) whose straight segment from (ox, oy) crosses no occupied
    cell, sampled every `spacing` cells (all segments in one vectorised lookup)."""
    t = np.asarray(targets, dtype=float).reshape(-1, 2)
    if t.size == 0:
        return np.zeros(0, dtype=bool)
    res = geometry.resolution
    lengths = np.hypot(t[:, 0] - ox, t[:, 1] - oy)
    counts = np.maximum(np.ceil(lengths / (spacing * res)).astype(int), 1)
    owner = np.repeat(np.arange(len(t)), counts)
    starts = np.cumsum(counts) - counts
    frac = (np.arange(owner.size) - starts[owner] + 0.5) / counts[owner]
    xs = ox + frac * (t[owner, 0] - ox)
    ys = oy + frac * (t[owner, 1] - oy)
    col = np.floor((xs - geometry.origin_x) / res).astype(np.int64)
    row = np.floor((ys - geometry.origin_y) / res).astype(np.int64)
    h, w = geometry.occupied.shape
    inside = (row >= 0) & (row < h) & (col >= 0) & (col < w)
    blocked = ~inside
    blocked[inside] = geometry.occupied[row[inside], col[inside]]
    return np.bincount(owner, weights=blocked, minlength=len(t)) == 0


@dataclass
class RangeTableConfig:
    """Resolution of the lookup table."""

    cell_size: float = 0.1        # [m] spacing of the table's sample points
    angle_bins: int = 1440        # [-] directions over 360 deg (1440 = UTM-30LX's 0.25 deg)
    min_clearance: float = 0.15   # [m] sample points closer to an obstacle are not tabulated
    max_range: float = 30.0       # [m] longest range stored (at most 32.766 m)
    max_shift: float = 0.3        # [m] largest correction from sample point to query point
                                  # (grazing hits; the face seldom continues that far)


class RangeTable:
    """Per-sample-point, per-direction ranges of one static map (uint16 entries).

    Entry = range in millimetres (bits 0-14) | hit face (bit 15: 1 = a face parallel to x).
    Occupied cells are axis-aligned squares, so the face a ray hits is either an x face or a
    y face; a parallel ray from a nearby point hits the same face at a range that differs by
    exactly dx / cos(theta) (x face) or dy / sin(theta) (y face) while the face continues.
    """

    MM = 1000.0
    FACE_BIT = np.uint16(1 << 15)
    RANGE_MASK = np.uint16((1 << 15) - 1)
    NO_HIT = (1 << 15) - 1          # 32.767 m: beyond every supported max_range

    def __init__(self, geometry: GridGeometry, config: RangeTableConfig, index: np.ndarray,
                 table: np.ndarray,
                 points: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        self.geometry, self.config = geometry, config
        self.index = index      # int32 (rows, cols): table row of each sample point, -1 if none
        self.table = table      # uint16 (n, angle_bins), see the class docstring
        # lazy table: the (xs, ys) of the sample points and which rows are filled; None when
        # every row was filled at build time
        self._points = points
        self._filled = None if points is None else np.zeros(len(points[0]), dtype=bool)
        self.bin_width = 2.0 * np.pi / config.angle_bins
        # 1/cos and 1/sin per bin, bounded so that no shift exceeds max_shift, stored twice over
        # so that any window of bins is a plain slice
        angles = np.arange(config.angle_bins) * self.bin_width
        bound = config.max_shift / (config.cell_size * math.sqrt(0.5))
        with np.errstate(divide="ignore"):
            inv_cos = np.clip(1.0 / np.cos(angles), -bound, bound).astype(np.float32)
            inv_sin = np.clip(1.0 / np.sin(angles), -bound, bound).astype(np.float32)
        self._inv_cos = np.concatenate([inv_cos, inv_cos])
        self._inv_sin = np.concatenate([inv_sin, inv_sin])

    @classmethod
    def build(cls, geometry: GridGeometry, config: RangeTableConfig | None = None,
              cache_dir: str | Path | None = None, chunk_rays: int = 2_000_000,
              lazy: bool = False) -> "RangeTable":
        """Tabulate every sample point with enough clearance; reuse a cached table if present.

        lazy: without a cached table, fill each row when a cast first needs it (the same
        entries; a robot in one corridor needs a few hundred of the map's rows, so a node or a
        one-off floor starts at once instead of after minutes); a lazy table is not cached.
        """
        config = config or RangeTableConfig()
        if config.max_range * cls.MM >= cls.NO_HIT:
            raise ValueError(f"RangeTable stores ranges below {cls.NO_HIT / cls.MM} m, "
                             f"max_range {config.max_range} m is too long")
        index, xs, ys = cls._sample_points(geometry, config)
        cache = cls._cache_path(geometry, config, cache_dir)
        if cache is not None and cache.is_file():
            table = np.load(cache)
            if table.shape == (xs.size, config.angle_bins):
                return cls(geometry, config, index, table)
        table = np.empty((xs.size, config.angle_bins), dtype=np.uint16)
        if lazy:
            return cls(geometry, config, index, table, points=(xs, ys))
        per_chunk = max(1, chunk_rays // config.angle_bins)
        for start in range(0, xs.size, per_chunk):
            stop = min(start + per_chunk, xs.size)
            table[start:stop] = cls._tabulate(geometry, config, xs[start:stop], ys[start:stop])
        if cache is not None:
            cache.parent.mkdir(parents=True, exist_ok=True)
            np.save(cache, table)
        return cls(geometry, config, index, table)

    @classmethod
    def _tabulate(cls, geometry: GridGeometry, config: RangeTableConfig, xs: np.ndarray,
                  ys: np.ndarray) -> np.ndarray:
        """Table rows (uint16 entries over every direction) of the sample points (xs, ys)."""
        angles = np.arange(config.angle_bins) * (2.0 * np.pi / config.angle_bins)
        ranges, faces = ray_march(geometry, xs[:, None], ys[:, None],
                                  np.broadcast_to(angles, (xs.size, angles.size)),
                                  config.max_range, return_faces=True)
        mm = np.where(np.isfinite(ranges), np.round(ranges * cls.MM), cls.NO_HIT)
        return mm.astype(np.uint16) | (faces.astype(np.uint16) << 15)

    @property
    def filled_rows(self) -> int:
        """How many rows hold ranges (all of them unless the table is lazy)."""
        return len(self.table) if self._filled is None else int(self._filled.sum())

    def _fill(self, entry: int) -> None:
        """Fill row `entry` of a lazy table if it is still empty."""
        if self._filled is not None and self._points is not None and not self._filled[entry]:
            xs, ys = self._points
            self.table[entry] = self._tabulate(self.geometry, self.config, xs[entry:entry + 1],
                                               ys[entry:entry + 1])[0]
            self._filled[entry] = True

    @staticmethod
    def _sample_points(geometry: GridGeometry, config: RangeTableConfig
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        g = geometry
        cols = int(np.floor(g.dist.shape[1] * g.resolution / config.cell_size))
        rows = int(np.floor(g.dist.shape[0] * g.resolution / config.cell_size))
        x = g.origin_x + (np.arange(cols) + 0.5) * config.cell_size
        y = g.origin_y + (np.arange(rows) + 0.5) * config.cell_size
        gx, gy = np.meshgrid(x, y)
        ok = g.clearance(gx, gy) >= config.min_clearance
        index = np.full(ok.shape, -1, dtype=np.int32)
        index[ok] = np.arange(int(ok.sum()), dtype=np.int32)
        return index, gx[ok], gy[ok]

    @staticmethod
    def _cache_path(geometry: GridGeometry, config: RangeTableConfig,
                    cache_dir: str | Path | None) -> Path | None:
        if cache_dir is None:
            return None
        digest = hashlib.sha256(np.packbits(geometry.occupied).tobytes())
        digest.update(repr((geometry.occupied.shape, geometry.resolution, geometry.origin_x,
                            geometry.origin_y, config, TABLE_FORMAT)).encode())
        return Path(cache_dir) / f"range_table_{digest.hexdigest()[:16]}.npy"

    def _nearest(self, x: float, y: float) -> tuple[int, float, float] | None:
        """(table row, dx, dy) of the sample point nearest to (x, y), or None if untabulated."""
        size = self.config.cell_size
        col = math.floor((x - self.geometry.origin_x) / size)
        row = math.floor((y - self.geometry.origin_y) / size)
        if not (0 <= row < self.index.shape[0] and 0 <= col < self.index.shape[1]):
            return None
        entry = int(self.index[row, col])
        if entry < 0:
            return None
        self._fill(entry)
        dx = x - (self.geometry.origin_x + (col + 0.5) * size)
        dy = y - (self.geometry.origin_y + (row + 0.5) * size)
        return entry, dx, dy

    def cast(self, x: float, y: float, angles: npt.ArrayLike) -> npt.NDArray[np.float32] | None:
        """Ranges [m] from (x, y) along `angles` [rad] (nearest table bin); None if untabulated.

        Values above max_range mean no return.
        """
        found = self._nearest(x, y)
        if found is None:
            return None
        bins = self._bins(np.asarray(angles, dtype=float))
        raw = self.table[found[0], bins]
        return self._shifted(raw, found[1], found[2], self._inv_cos[bins],
                             self._inv_sin[bins])

    def _bins(self, angles: np.ndarray) -> npt.NDArray[np.int64]:
        """Nearest table bin of each angle [rad], in [-angle_bins, angle_bins): numpy's
        negative indices address the table and the doubled inverse cos / sin arrays as their
        remainder modulo angle_bins would, so angles within +-2 pi (a wrapped yaw plus a beam
        angle) skip the integer modulo, which took a sixth of a batch cast's time."""
        bins = np.rint(angles / self.bin_width).astype(np.int64)
        count = self.config.angle_bins
        if bins.size and (bins.min() < -count or bins.max() >= count):
            bins %= count
        return bins

    def cast_fan(self, x: float, y: float, first_angle: float, count: int,
                 step_bins: int) -> npt.NDArray[np.float32] | None:
        """Like cast for `count` beams `step_bins` table bins apart from first_angle [rad]."""
        found = self._nearest(x, y)
        if found is None:
            return None
        n = self.config.angle_bins
        k0 = int(round(first_angle / self.bin_width)) % n
        span = (count - 1) * step_bins + 1
        row = self.table[found[0]]
        if k0 + span > n:                       # the fan wraps past bin 0
            row = np.concatenate((row, row[:k0 + span - n]))
        window = slice(k0, k0 + span, step_bins)
        return self._shifted(row[window], found[1], found[2], self._inv_cos[window],
                             self._inv_sin[window])

    def cast_rows(self, xs: Sequence[float], ys: Sequence[float], yaws: Sequence[float],
                  angles: np.ndarray, fan_step: int = 0) -> npt.NDArray[np.float32] | None:
        """`cast` from several points at once: row k is cast(xs[k], ys[k], angles + yaws[k]),
        or with `fan_step` cast_fan(xs[k], ys[k], yaws[k] + angles[0], len(angles), fan_step),
        value for value; None when a point is untabulated."""
        found = [self._nearest(x, y) for x, y in zip(xs, ys)]
        if None in found:
            return None
        entries, dx, dy = (np.array(column)[:, None] for column in zip(*found))
        count = self.config.angle_bins
        if fan_step:
            first = [int(round((yaw + angles[0]) / self.bin_width)) % count for yaw in yaws]
            bins = np.array(first)[:, None] + np.arange(len(angles)) * fan_step
            inv_cos, inv_sin = self._inv_cos[bins], self._inv_sin[bins]   # stored twice over
            bins[bins >= count] -= count
        else:
            world_angles = np.asarray(angles, dtype=float)[None, :] + np.asarray(yaws)[:, None]
            bins = self._bins(world_angles)
            inv_cos, inv_sin = self._inv_cos[bins], self._inv_sin[bins]
        return self._shifted(self.table[entries, bins], dx, dy, inv_cos, inv_sin)

    def _shifted(self, raw: np.ndarray, dx: float | np.ndarray, dy: float | np.ndarray,
                 inv_cos: np.ndarray, inv_sin: np.ndarray) -> npt.NDArray[np.float32]:
        """Table ranges moved from the sample point by (dx, dy) along each hit face (dx, dy:
        numbers, or columns for rows of ranges)."""
        ranges = (raw & self.RANGE_MASK).astype(np.float32)
        ranges *= np.float32(1.0 / self.MM)
        ranges -= np.where(raw >= self.FACE_BIT, np.float32(dy) * inv_sin,
                           np.float32(dx) * inv_cos)
        return ranges
