"""Shared test fixtures: hand-made occupancy grids and a kinematic loop for the move_base core."""
import math

import numpy as np
from floorplan.occupancy_map import FREE, OCCUPIED, UNKNOWN, OccupancyMap


def grid_from_rows(rows, resolution=0.1):
    """'#' occupied, '.' free, '?' unknown; the first text row is grid row 0 (y = 0)."""
    lookup = {"#": OCCUPIED, ".": FREE, "?": UNKNOWN}
    cells = np.array([[lookup[ch] for ch in row] for row in rows], dtype=np.int8)
    return OccupancyMap(cells=cells, resolution=resolution, origin=(0.0, 0.0, 0.0))


def open_room(width_cells, height_cells, resolution=0.1):
    """A free rectangle with a one-cell wall all around."""
    cells = np.full((height_cells, width_cells), FREE, dtype=np.int8)
    cells[0, :] = cells[-1, :] = cells[:, 0] = cells[:, -1] = OCCUPIED
    return OccupancyMap(cells=cells, resolution=resolution, origin=(0.0, 0.0, 0.0))


def integrate(pose, cmd, dt):
    """Holonomic kinematics: base-frame (vx, vy, wz) applied for dt."""
    x, y, th = pose
    vx, vy, wz = cmd
    return (x + (vx * math.cos(th) - vy * math.sin(th)) * dt,
            y + (vx * math.sin(th) + vy * math.cos(th)) * dt, th + wz * dt)


def synthetic_scan(world_occupied, grid, pose, beams=180, max_range=4.0, step=0.01):
    """Reference laser for tests: march each beam in `step` metres until an occupied cell."""
    from nav_mocks.scan_rays import Scan
    angles = np.linspace(-math.pi, math.pi, beams, endpoint=False)
    r = np.arange(step, max_range, step)
    a = angles[:, None] + pose[2]
    rows, cols = grid.world_to_cell(pose[0] + r * np.cos(a), pose[1] + r * np.sin(a))
    inside = grid.inside(rows, cols)
    blocked = ~inside
    blocked[inside] = world_occupied[rows[inside], cols[inside]]
    first = np.argmax(blocked, axis=1)
    ranges = np.where(blocked.any(axis=1), r[first], np.inf)
    return Scan(angles, ranges, 0.05, max_range)
