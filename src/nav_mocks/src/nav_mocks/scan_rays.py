"""Laser scans as geometry: hit points in the map frame and the grid cells each beam crossed.

ROS-free. A scan is (angles [rad] in the laser frame, ranges [m]); a pose is (x, y, yaw) of the
laser in the map frame. Ranges that are not finite or lie outside [range_min, range_max] are no
hit; a beam that returned range_max or more still clears the cells it crossed (as costmap_2d and
GMapping treat max-range readings).
"""
from dataclasses import dataclass

import numpy as np

HIT_NUDGE = 0.1  # [cells] a return is looked up this far past the measured range


@dataclass
class Scan:
    """One laser scan, as sensor_msgs/LaserScan holds it."""

    angles: np.ndarray   # (N,) beam angles in the laser frame [rad]
    ranges: np.ndarray   # (N,) measured ranges [m]; inf/nan = no return
    range_min: float     # [m]
    range_max: float     # [m]

    def hits(self):
        """Boolean (N,): beams that returned a real obstacle."""
        r = self.ranges
        return np.isfinite(r) & (r >= self.range_min) & (r < self.range_max)


def hit_points(scan, pose, max_range=np.inf):
    """(M, 2) map-frame points of the beams that hit something closer than max_range."""
    x, y, yaw = pose
    keep = scan.hits() & (scan.ranges <= max_range)
    a = scan.angles[keep] + yaw
    r = scan.ranges[keep]
    return np.column_stack((x + r * np.cos(a), y + r * np.sin(a)))


def beam_cells(scan, pose, grid, clear_range, mark_range):
    """Cells each beam crossed (free) and the cells it ended in (hit), inside `grid`.

    Beams are sampled every half cell up to min(range, clear_range); the hit cell of a beam
    with a return closer than mark_range is marked, and is never also reported free.

    Args:
        grid: an object with resolution, origin, world_to_cell and inside (OccupancyMap).
    Returns:
        (free, hit): each a (rows, cols) tuple of index arrays.
    """
    x, y, yaw = pose
    ranges = np.where(np.isfinite(scan.ranges), scan.ranges, scan.range_max)
    reach = np.clip(ranges, 0.0, min(clear_range, scan.range_max))
    step = 0.5 * grid.resolution
    samples = np.arange(0.0, reach.max(initial=0.0) + step, step)
    along = np.minimum(samples[None, :], reach[:, None] - 1e-6)   # (N, S): never past the return
    a = (scan.angles + yaw)[:, None]
    rows, cols = grid.world_to_cell(x + along * np.cos(a), y + along * np.sin(a))
    hit = scan.hits() & (scan.ranges <= mark_range)
    past = scan.ranges[hit] + HIT_NUDGE * grid.resolution  # a return on a cell face: that cell
    hx = x + past * np.cos(scan.angles[hit] + yaw)
    hy = y + past * np.sin(scan.angles[hit] + yaw)
    hit_rows, hit_cols = grid.world_to_cell(hx, hy)
    inside = grid.inside(hit_rows, hit_cols)
    hit_rows, hit_cols = hit_rows[inside], hit_cols[inside]
    rows, cols = rows.ravel(), cols.ravel()
    inside = grid.inside(rows, cols)
    rows, cols = rows[inside], cols[inside]
    hit_flat = np.unique(hit_rows * grid.width + hit_cols)
    free_flat = np.setdiff1d(np.unique(rows * grid.width + cols), hit_flat)
    return (free_flat // grid.width, free_flat % grid.width), (hit_rows, hit_cols)
