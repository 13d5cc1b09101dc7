"""Helpers shared by the sim2d tests (a uniquely named module: every package has a conftest)."""

import numpy as np

from floorplan.occupancy_map import FREE, OCCUPIED, OccupancyMap
from tamp_resources import resource

REPO = resource()
LASER_DIR = REPO / "config" / "lasers"
RESOLUTION = 0.05


def room_grid():
    """10 m x 10 m free square, 0.1 m outer walls, and a wall x in [5.0, 5.2] for y < 8 m."""
    cells = np.full((200, 200), FREE, dtype=np.int8)
    cells[:2, :] = cells[-2:, :] = cells[:, :2] = cells[:, -2:] = OCCUPIED
    cells[:160, 100:104] = OCCUPIED
    return OccupancyMap(cells=cells, resolution=RESOLUTION, origin=(0.0, 0.0, 0.0))
