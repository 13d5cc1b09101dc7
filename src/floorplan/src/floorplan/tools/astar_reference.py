"""The benchmark's reference grid planner: a pure-Python A* (heapq on flat cell indices, compact
`array`/`bytearray` state, octile heuristic, ties in f broken towards the larger g), with the
same move rules, cost model and return value as `floorplan.astar.astar`.

`scripts/bench_astar` times `astar` against it and `test_astar.py` checks that both find paths of
the same length. Nothing else uses it.
"""
import heapq
import math
from array import array

import numpy as np

from floorplan.astar import SQRT2, GridPath, check_cell, inflate_obstacles


def reference_astar(obstacles, start, goal, resolution=1.0, robot_radius=0.0, cell_penalty=None):
    """Pure-Python A* (heapq on flat cell indices): shortest 8-connected path from `start` to
    `goal` (row, col) through free cells.

    Args:
        obstacles: bool array (H, W), True = blocked.
        resolution: cell side [m].
        robot_radius: obstacles are inflated by this radius first [m]; 0 = no inflation.
        cell_penalty: optional float array (H, W) >= 0 added to the cost of entering a cell
            [cells of length], as navfn adds costmap cost; the octile heuristic stays admissible.
    Returns:
        GridPath, or None when the goal cannot be reached (or start/goal are blocked).
    """
    blocked = inflate_obstacles(obstacles, resolution, robot_radius)
    check_cell("start", start, blocked.shape)
    check_cell("goal", goal, blocked.shape)
    if blocked[start] or blocked[goal]:
        return None
    padded = np.pad(blocked, 1, constant_values=True)  # border of obstacles: no bounds checks
    width = padded.shape[1]
    to_flat = lambda cell: (cell[0] + 1) * width + cell[1] + 1  # noqa: E731
    penalty = None
    if cell_penalty is not None:
        cell_penalty = np.asarray(cell_penalty, dtype=float)
        if cell_penalty.shape != blocked.shape or (cell_penalty < 0).any():
            raise ValueError(f"A*: cell_penalty must be >= 0 with shape {blocked.shape}")
        penalty = array("d", np.pad(cell_penalty, 1).ravel().tobytes())
    parent = _search(padded.ravel().tobytes(), width, to_flat(start), to_flat(goal), penalty)
    if parent is None:
        return None
    return _trace(parent, width, to_flat(start), to_flat(goal), resolution)


def _search(blocked, width, start, goal, penalty=None):
    """A* on flat indices; returns the parent array, or None if the goal is unreachable.

    Ties in f are broken towards the larger g (the node nearer the goal), which on open grids
    expands far fewer of the many equal-f cells without changing the optimal length.
    """
    goal_row, goal_col = divmod(goal, width)
    # (offset, step length, corner offsets that must both be free for a diagonal; 0 = straight)
    moves = ((1, 1.0, 0, 0), (-1, 1.0, 0, 0), (width, 1.0, 0, 0), (-width, 1.0, 0, 0),
             (width + 1, SQRT2, width, 1), (width - 1, SQRT2, width, -1),
             (-width + 1, SQRT2, -width, 1), (-width - 1, SQRT2, -width, -1))
    octile = SQRT2 - 2.0
    cost = array("d", [math.inf]) * len(blocked)
    parent = array("l", [-1]) * len(blocked)
    closed = bytearray(len(blocked))
    cost[start] = 0.0
    frontier = [(0.0, 0.0, start)]
    push, pop = heapq.heappush, heapq.heappop
    while frontier:
        _, _, cell = pop(frontier)
        if closed[cell]:
            continue
        if cell == goal:
            return parent
        closed[cell] = 1
        base = cost[cell]
        for offset, step, corner_a, corner_b in moves:
            nxt = cell + offset
            if blocked[nxt] or closed[nxt]:
                continue
            if corner_a and (blocked[cell + corner_a] or blocked[cell + corner_b]):
                continue
            new_cost = base + step
            if penalty is not None:
                new_cost += penalty[nxt]
            if new_cost >= cost[nxt]:
                continue
            cost[nxt] = new_cost
            parent[nxt] = cell
            row, col = divmod(nxt, width)
            dr = row - goal_row if row > goal_row else goal_row - row
            dc = col - goal_col if col > goal_col else goal_col - col
            heuristic = dr + dc + octile * (dr if dr < dc else dc)   # octile distance
            push(frontier, (new_cost + heuristic, -new_cost, nxt))
    return None


def _trace(parent, width, start, goal, resolution):
    """Follow parents back from the goal; cells are returned in unpadded (row, col)."""
    flat = [goal]
    while flat[-1] != start:
        flat.append(parent[flat[-1]])
    flat.reverse()
    cells = [(idx // width - 1, idx % width - 1) for idx in flat]
    length = sum(SQRT2 if (a[0] != b[0] and a[1] != b[1]) else 1.0
                 for a, b in zip(cells, cells[1:]))
    return GridPath(cells=cells, length_m=length * resolution)
