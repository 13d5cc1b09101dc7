"""Shared test fixtures: hand-made occupancy grids and a kinematic loop for the move_base core."""
import math

import numpy as np
from sim2d.occupancy_map import FREE, OCCUPIED, UNKNOWN, OccupancyMap


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
