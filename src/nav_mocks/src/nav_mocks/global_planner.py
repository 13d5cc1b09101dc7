"""Global planner of the move_base mock: grid A* on the inflated costmap (navfn/global_planner).

ROS-free. Cells at or above the inscribed cost are blocked; cheaper inflated cells cost extra in
proportion to their cost (navfn's cost factor), so plans keep away from walls where there is room.
When the robot stands in an inscribed cell, its footprint is cleared first (costmap_2d's
clearRobotCell, widened to the whole inscribed disk) so that it can still leave; otherwise the
plan keeps to cells the local controller will accept. A goal tolerance (nav_msgs/GetPlan's
`tolerance`) lets a blocked or unreachable goal be replaced by the nearest reachable free cell
within that many metres in x and y, as navfn does. `nearest_free_cell` finds the nearest free cell
reachable from the start within a disc round a blocked goal (the move_base core's goal search).
"""
from dataclasses import dataclass

import cv2
import numpy as np

from floorplan.astar import astar
from nav_mocks.costmap import (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION,
                               cost_penalty)


@dataclass
class PlannerConfig:
    cost_factor: float = 3.0   # [cells] extra length for crossing a cell of cost 252


@dataclass
class Plan:
    points: np.ndarray   # (N, 2) map-frame waypoints [m], start first, goal last
    length_m: float      # [m] length of the polyline


class NoPath(Exception):
    """No plan exists; the message says why (for an ABORTED result or a make_plan reply)."""


def polyline_length(points):
    return float(np.hypot(*np.diff(points, axis=0).T).sum()) if len(points) > 1 else 0.0


def _footprint_cells(grid, x, y, radius):
    """Boolean mask of the cells whose centres lie within `radius` of (x, y)."""
    rows, cols = np.ogrid[:grid.height, :grid.width]
    cx, cy = grid.cell_to_world(rows, cols)
    return np.hypot(cx - x, cy - y) <= radius


class GlobalPlanner:
    """Plans on a Costmap (nav_mocks.costmap.Costmap)."""

    def __init__(self, costmap, config=None):
        self.costmap = costmap
        self.config = config or PlannerConfig()

    def cell_of(self, x, y, what):
        grid = self.costmap.grid
        row, col = grid.world_to_cell(x, y)
        if not grid.inside(row, col):
            raise NoPath(f"{what} ({x:.2f}, {y:.2f}) lies outside the map")
        return int(row), int(col)

    def plan(self, start_xy, goal_xy, tolerance=0.0):
        """A Plan from start to goal, or NoPath naming the reason.

        tolerance [m] (nav_msgs/GetPlan): when the goal cell is blocked (an obstacle, closer than
        the robot radius to one) or cannot be reached, plan instead to the nearest free cell
        reachable from the start whose centre lies within `tolerance` of the goal in x and in y
        (navfn's square window); the plan then ends at that cell's centre. 0 plans to the goal
        exactly.
        """
        if not (tolerance >= 0.0 and np.isfinite(tolerance)):
            raise NoPath(f"tolerance {tolerance} must be a finite number >= 0")
        grid = self.costmap.grid
        start = self.cell_of(*start_xy, "start")
        goal = self.cell_of(*goal_xy, "goal")
        costs = self.costmap.costs()
        blocked = self.blocked_cells(start_xy)
        goal_end = goal_xy[:2]
        if tolerance > 0.0 and (blocked[goal] or not reachable_cells(blocked, start)[goal]):
            goal = _nearest_reachable(grid, blocked, start, goal_xy, tolerance)
            if goal is not None:
                goal_end = tuple(float(v) for v in grid.cell_to_world(*goal))
            else:
                goal = self.cell_of(*goal_xy, "goal")   # nothing within tolerance: say why
        if costs[goal] == LETHAL_OBSTACLE:
            raise NoPath(f"goal ({goal_xy[0]:.2f}, {goal_xy[1]:.2f}) lies in an obstacle")
        if INSCRIBED_INFLATED_OBSTACLE <= costs[goal] < NO_INFORMATION:
            raise NoPath(f"goal ({goal_xy[0]:.2f}, {goal_xy[1]:.2f}) is closer than the robot "
                         "radius to an obstacle")
        found = astar(blocked, start, goal, grid.resolution,
                      cell_penalty=cost_penalty(costs, self.config.cost_factor))
        if found is None:
            raise NoPath(f"no path from ({start_xy[0]:.2f}, {start_xy[1]:.2f}) to "
                         f"({goal_xy[0]:.2f}, {goal_xy[1]:.2f}) on the costmap")
        rows, cols = np.array(found.cells).T
        xs, ys = grid.cell_to_world(rows, cols)
        points = np.column_stack((xs, ys))
        points[0] = start_xy[:2]
        points[-1] = goal_end
        return Plan(points=points, length_m=polyline_length(points))

    def blocked_cells(self, start_xy):
        """Boolean mask of the cells a plan from start_xy may not cross: cost >= inscribed, except
        unknown cells (255 exists only when unknown space is not lethal) and, when the start
        cell is blocked, the non-lethal cells of the robot's padded footprint (the way out)."""
        grid = self.costmap.grid
        start = self.cell_of(*start_xy, "start")
        costs = self.costmap.costs()
        blocked = (costs >= INSCRIBED_INFLATED_OBSTACLE) & (costs != NO_INFORMATION)
        if blocked[start]:   # only a robot already too close to an obstacle needs a way out
            footprint = _footprint_cells(grid, start_xy[0], start_xy[1],
                                         self.costmap.config.inscribed_radius)
            blocked[footprint & (costs != LETHAL_OBSTACLE)] = False
            blocked[start] = False
        return blocked


def reachable_cells(blocked, start):
    """Boolean mask of the cells A* can reach from `start` over free cells.

    A* forbids cutting corners, so a diagonal step is allowed only where both orthogonal steps
    are: its reachable set is exactly the 4-connected component of the start."""
    _, labels = cv2.connectedComponents((~blocked).astype(np.uint8), connectivity=4)
    return (labels == labels[start]) & ~blocked


def goal_cells(costs):
    """Boolean mask of the cells a plan may end on: not closer than the robot radius to an
    obstacle (`plan` refuses such a goal even where blocked_cells lets the robot leave its own
    footprint), or unknown."""
    return (costs < INSCRIBED_INFLATED_OBSTACLE) | (costs == NO_INFORMATION)


def nearest_free_cell(grid, blocked, start, goal_xy, radius, ends=None):
    """(row, col) of the free cell reachable from the `start` cell whose centre lies nearest
    goal_xy (x, y) [m] and no farther than `radius` [m] from it (a disc); None when there is
    none. blocked: boolean mask (GlobalPlanner.blocked_cells) of the cells a plan may not cross;
    ends: mask of the cells allowed as the result (goal_cells), None = every free one."""
    if not (radius >= 0.0 and np.isfinite(radius)):
        raise ValueError(f"search radius {radius} must be a finite number >= 0")
    reach = reachable_cells(blocked, start)
    rows, cols = np.nonzero(reach if ends is None else reach & ends)
    xs, ys = grid.cell_to_world(rows, cols)
    squared = (xs - goal_xy[0]) ** 2 + (ys - goal_xy[1]) ** 2
    inside = squared <= radius ** 2 + 1e-9
    if not inside.any():
        return None
    best = int(np.argmin(np.where(inside, squared, np.inf)))
    return int(rows[best]), int(cols[best])


def _nearest_reachable(grid, blocked, start, goal_xy, tolerance):
    """(row, col) of the reachable free cell nearest goal_xy with its centre within `tolerance`
    [m] of it in x and y; None when there is none."""
    rows, cols = np.nonzero(reachable_cells(blocked, start))
    xs, ys = grid.cell_to_world(rows, cols)
    dx, dy = np.abs(xs - goal_xy[0]), np.abs(ys - goal_xy[1])
    inside = (dx <= tolerance + 1e-9) & (dy <= tolerance + 1e-9)
    if not inside.any():
        return None
    best = int(np.argmin(np.where(inside, dx ** 2 + dy ** 2, np.inf)))
    return int(rows[best]), int(cols[best])
