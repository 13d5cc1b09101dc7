"""GMapping mock: a map revealed progressively from what the robot's laser has seen.

ROS-free. The true map is known (it is the simulator's world); a cell becomes known once a beam
crossed it (free) or ended in it (occupied), the way GMapping's occupancy grid grows around the
robot's trajectory. Unseen cells stay UNKNOWN (-1), as in a GMapping map being built.
"""
import numpy as np
from floorplan.occupancy_map import UNKNOWN, OccupancyMap

from nav_mocks.scan_rays import beam_cells


class RevealedMap:
    """The part of `truth` (an OccupancyMap) that the laser has seen so far."""

    def __init__(self, truth, max_range):
        """`max_range` [m]: GMapping's maxUrange, beams are used up to this range."""
        if max_range <= 0:
            raise ValueError(f"mapping: max_range must be > 0, got {max_range}")
        self.truth = truth
        self.max_range = float(max_range)
        self.known = np.zeros(truth.cells.shape, dtype=bool)

    def integrate_scan(self, scan, laser_pose):
        """Reveal the cells crossed by and hit by the beams of `scan` taken at `laser_pose`.

        Returns the number of cells newly revealed.
        """
        free, hit = beam_cells(scan, laser_pose, self.truth, self.max_range, self.max_range)
        before = int(self.known.sum())
        self.known[free] = True
        self.known[hit] = True
        return int(self.known.sum()) - before

    def current(self):
        """The map built so far: true values where seen, UNKNOWN elsewhere."""
        cells = np.where(self.known, self.truth.cells, np.int8(UNKNOWN)).astype(np.int8)
        return OccupancyMap(cells=cells, resolution=self.truth.resolution,
                            origin=self.truth.origin)

    def explored_fraction(self):
        return float(self.known.mean())
