"""Continuous clearance for the local controller: the contact region in map coordinates.

ROS-free. A grid contact test (sim2d's, or a bumper model on the map's cells) decides contact
from the cell that holds the robot centre: the cell is in contact when the distance between its
centre and the nearest occupied cell's centre, less the cell bound sqrt(2) * resolution, is below
the robot radius (contact_clearance). The cells that pass form the admissible region A, a union of
squares. What the controller must keep is the TRUE robot centre inside A, while it knows only the
estimated pose: with a localisation error below `margin`, it suffices that the estimated centre
lies at least `margin` inside A. That depth (the Euclidean distance from a point to the nearest
square outside A) is tabulated once per static map on cells `subdivision` times finer than the
map (costmap.signed_depth_field; a lower bound off by at most sqrt(2) fine cells, 7 mm at 0.05 m
and 10), not looked up at the estimate's map cell: that lookup jumps by a whole cell whenever the
estimate crosses a cell edge, which made one-cell-wide bands of admissible cells impassable
(or, with a smaller limit, let the true centre slip into the next cell).

Obstacles not on the map (laser hits farther than static_match_distance from a map obstacle) are
kept as points; their clearance is the Euclidean distance to the nearest hit.

`ContactClearance.clearance(x, y)` returns, in metres,
    min(robot_radius + depth_A(x, y), distance to the nearest unmapped laser hit),
so that a clearance of robot_radius + margin means "margin from contact" for both kinds of
obstacle, and the DWA compares it with one limit (collision_radius).
"""
import numpy as np
from scipy.spatial import cKDTree

OFF_GRID_DEPTH = -1.0                 # [m] depth of a point off the map (always outside)


class ContactClearance:
    """Clearance [m] of map points for the DWA: the contact region A of the static map plus the
    laser hits of obstacles the map does not have (see the module docstring)."""

    def __init__(self, depth_field, subdivision, grid, robot_radius, points):
        """depth_field: signed_depth_field of the region A on `grid`, `subdivision` times finer;
        points: (M, 2) map-frame laser hits of unmapped obstacles [m]."""
        self.grid = grid
        self.depth_field = depth_field
        self.fine = grid.resolution / subdivision      # [m] side of a fine cell
        self.robot_radius = robot_radius
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        self.tree = cKDTree(points) if len(points) else None

    def depth(self, x, y):
        """Lower bound [m] of the signed distance of map points into A (off by at most
        sqrt(2) fine cells); OFF_GRID_DEPTH off the map."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        col = np.floor((x - self.grid.origin[0]) / self.fine).astype(int)
        row = np.floor((y - self.grid.origin[1]) / self.fine).astype(int)
        h, w = self.depth_field.shape
        on = (row >= 0) & (row < h) & (col >= 0) & (col < w)
        out = np.full(x.shape, OFF_GRID_DEPTH)
        out[on] = self.depth_field[row[on], col[on]] * self.fine
        return out

    def hit_distance(self, x, y):
        """Distance [m] from map points to the nearest unmapped laser hit (inf without hits)."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        if self.tree is None:
            return np.full(x.shape, np.inf)
        return self.tree.query(np.column_stack((x.ravel(), y.ravel())))[0].reshape(x.shape)

    def clearance(self, x, y):
        """min(robot_radius + depth in A, distance to the nearest unmapped hit) [m]."""
        return np.minimum(self.robot_radius + self.depth(x, y), self.hit_distance(x, y))

    def collision_radius(self, costmap_config, margin):
        """[m] clearance a trajectory must keep: `margin` from contact."""
        return costmap_config.robot_radius + margin
