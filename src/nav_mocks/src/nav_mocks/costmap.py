"""Costmap with costmap_2d semantics: static layer, obstacle layer from the laser, inflation layer.

ROS-free. Cell costs follow costmap_2d (cost_values.h): 0 free, 253 inscribed (the robot centre
there means a collision), 254 lethal (an obstacle), 255 no information; between the inscribed
radius and the inflation radius the cost decays exponentially (InflationLayer::computeCost).
"""
import math
from dataclasses import dataclass

import cv2
import numpy as np

FREE_SPACE = 0
INSCRIBED_INFLATED_OBSTACLE = 253
LETHAL_OBSTACLE = 254
NO_INFORMATION = 255
CELL_CLEARANCE_LOSS = math.sqrt(2.0)  # [cells] a point to its cell centre plus an obstacle cell's
                                      # centre to its edge: half a cell diagonal each


@dataclass
class CostmapConfig:
    """Parameters named as in costmap_2d's inflation and obstacle layers."""

    robot_radius: float = 0.25          # [m] circular footprint
    footprint_padding: float = 0.05     # [m] added to the footprint (covers cell discretisation)
    inflation_radius: float = 0.55      # [m] costs fall to 0 beyond this distance
    cost_scaling_factor: float = 10.0   # [1/m] exponential decay rate of the inflated cost
    unknown_is_lethal: bool = True      # [-] track_unknown_space=false: unknown is an obstacle
    obstacle_range: float = 2.5         # [m] scan hits farther than this are not marked
    raytrace_range: float = 3.0         # [m] cells along a beam up to this range are cleared
    static_match_distance: float = 0.15  # [m] hits this close to a map obstacle are that obstacle

    @property
    def inscribed_radius(self):
        """[m] padded robot radius: a robot centre closer than this to an obstacle collides."""
        return self.robot_radius + self.footprint_padding

    def validate(self):
        if self.robot_radius < 0 or self.footprint_padding < 0:
            raise ValueError("costmap: robot_radius and footprint_padding must be >= 0")
        if self.inscribed_radius > self.inflation_radius:
            raise ValueError("costmap: need robot_radius + footprint_padding <= inflation_radius, "
                             f"got {self.inscribed_radius} > {self.inflation_radius}")
        if self.cost_scaling_factor <= 0:
            raise ValueError(f"costmap: cost_scaling_factor must be > 0, "
                             f"got {self.cost_scaling_factor}")


def inflation_cost(distance_m, config):
    """costmap_2d InflationLayer::computeCost: cost of a cell at `distance_m` from an obstacle.

    254 at distance 0, 253 within the inscribed radius, else 252 * exp(-k (d - r_inscribed))
    up to the inflation radius, 0 beyond it (the result is truncated to an integer cost).
    """
    d = np.asarray(distance_m, dtype=float)
    decayed = (INSCRIBED_INFLATED_OBSTACLE - 1) * np.exp(
        -config.cost_scaling_factor * (d - config.inscribed_radius))
    cost = np.where(d <= config.inscribed_radius, INSCRIBED_INFLATED_OBSTACLE,
                    np.where(d <= config.inflation_radius, decayed, FREE_SPACE))
    cost = np.where(d <= 0.0, LETHAL_OBSTACLE, cost)
    return cost.astype(np.uint8)


def obstacle_distance(lethal):
    """Euclidean distance [cells] from each cell centre to the nearest lethal cell centre."""
    if not lethal.any():
        return np.full(lethal.shape, np.inf)
    free = np.ascontiguousarray(~lethal, dtype=np.uint8)
    return cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE).astype(float)


def contact_clearance(robot_radius, resolution, margin):
    """[m] cell-centre clearance below which the robot may touch an obstacle.

    Clearance on the grid is the distance between cell centres; the robot centre may lie half a
    cell diagonal from its cell's centre and the obstacle's edge half a diagonal from the obstacle
    cell's centre, so a cell-centre distance d guarantees only d - sqrt(2) * resolution of free
    space (the bound a simulator's or a bumper's collision test on the same grid uses).
    """
    return robot_radius + CELL_CLEARANCE_LOSS * resolution + margin


def admissible_cells(obstacle_distance_m, robot_radius, resolution):
    """Boolean mask of the region A: cells the grid contact test accepts for the robot centre.

    obstacle_distance_m: (H, W) distance [m] from each cell centre to the nearest obstacle cell
    centre. A cell passes when that distance less the cell bound is at least the robot radius
    (sim2d.kinematics.step_robot refuses a step when it is below)."""
    return obstacle_distance_m >= contact_clearance(robot_radius, resolution, 0.0) - 1e-9


def signed_depth_field(inside, subdivision):
    """Signed distance [fine cells] of the cells of a grid `subdivision` times finer than
    `inside` to the boundary of the union of the `inside` squares, as a lower bound for any
    point of the fine cell: inside, the distance between the fine cell's centre and the nearest
    outside fine cell's centre less sqrt(2) (the point may lie half a fine diagonal from its
    centre, the outside square's edge half a diagonal from that centre); outside, minus the
    distance to the nearest inside fine cell's centre. The union of the coarse squares is exactly
    the union of their fine cells, so the bound is off by at most sqrt(2) fine cells."""
    fine = np.repeat(np.repeat(inside, subdivision, axis=0), subdivision, axis=1)
    to_outside = obstacle_distance(~fine)
    to_inside = obstacle_distance(fine)
    return np.where(fine, to_outside - CELL_CLEARANCE_LOSS, -to_inside).astype(np.float32)


def inflate(lethal, resolution, config):
    """The inflation layer over a lethal mask: uint8 costs (H, W) with costmap_2d values."""
    return inflation_cost(obstacle_distance(lethal) * resolution, config)


class Costmap:
    """A global costmap over a static grid: static + obstacle (laser) + inflation layers."""

    def __init__(self, grid, config=None):
        """`grid` is a floorplan.occupancy_map.OccupancyMap (the static map)."""
        self.config = config or CostmapConfig()
        self.config.validate()
        self.grid = grid
        self.static_lethal = grid.cells >= 50
        self.unknown = grid.cells < 0
        self.marked = np.zeros(grid.cells.shape, dtype=bool)   # obstacle layer
        self._costs = None
        self._static_distance = None
        self._contact_region = None

    @property
    def resolution(self):
        return self.grid.resolution

    def set_static(self, grid):
        """Replace the static layer (a new /map, e.g. from the mapping mock)."""
        if grid.cells.shape != self.grid.cells.shape:
            self.marked = np.zeros(grid.cells.shape, dtype=bool)
        self.grid = grid
        self.static_lethal = grid.cells >= 50
        self.unknown = grid.cells < 0
        self._costs = None
        self._static_distance = None
        self._contact_region = None

    def static_distance(self):
        """Distance [m] from each cell centre to the nearest obstacle of the static map."""
        if self._static_distance is None:
            self._static_distance = obstacle_distance(self.static_lethal) * self.resolution
        return self._static_distance

    def contact_depth(self, subdivision):
        """signed_depth_field [fine cells] of the cells where the robot centre passes the grid
        contact test against the static map (admissible_cells; unknown counts as an obstacle
        when it is lethal), `subdivision` times finer than the map. Cached until the static
        layer changes."""
        if self._contact_region is None or self._contact_region[0] != subdivision:
            obstacles = self.static_lethal
            if self.config.unknown_is_lethal:
                obstacles = obstacles | self.unknown
            distance = obstacle_distance(obstacles) * self.resolution
            admissible = admissible_cells(distance, self.config.robot_radius, self.resolution)
            self._contact_region = (subdivision, signed_depth_field(admissible, subdivision))
        return self._contact_region[1]

    def new_obstacle(self, rows, cols):
        """Boolean mask over hit cells: True where a hit is not a wall of the static map.

        A laser hit within static_match_distance of a map obstacle is that obstacle seen with
        range noise; marking it would grow the walls by the noise and close narrow doors.
        """
        return self.static_distance()[rows, cols] > self.config.static_match_distance

    def lethal(self):
        lethal = self.static_lethal | self.marked
        if self.config.unknown_is_lethal:
            lethal = lethal | self.unknown
        return lethal

    def costs(self):
        """uint8 (H, W) master costs: inflated lethal cells; unknown is 255 unless lethal."""
        if self._costs is None:
            costs = inflate(self.lethal(), self.resolution, self.config)
            if not self.config.unknown_is_lethal:
                costs[self.unknown] = NO_INFORMATION
            self._costs = costs
        return self._costs

    def update_from_scan(self, free_cells, hit_cells):
        """Obstacle layer: clear the cells a beam crossed, then mark its hit cells.

        Args: (rows, cols) index arrays, as returned by scan_rays.beam_cells (inside the grid).
        """
        self.marked[free_cells] = False
        rows, cols = hit_cells
        keep = self.new_obstacle(rows, cols)
        self.marked[rows[keep], cols[keep]] = True
        self._costs = None

    def clear_obstacles(self):
        """The 'clear costmaps' recovery: forget every laser mark, keep the static map."""
        self.marked[:] = False
        self._costs = None

    def cost_at(self, x, y):
        """Cost of the cell holding map point (x, y); NO_INFORMATION outside the grid."""
        row, col = self.grid.world_to_cell(x, y)
        if not self.grid.inside(row, col):
            return NO_INFORMATION
        return int(self.costs()[row, col])


def cost_penalty(costs, weight):
    """navfn-style planning penalty per cell [cells of length]: weight * cost / 252."""
    penalty = costs.astype(float) * (weight / (INSCRIBED_INFLATED_OBSTACLE - 1))
    penalty[costs >= INSCRIBED_INFLATED_OBSTACLE] = 0.0  # those cells are blocked anyway
    return penalty

