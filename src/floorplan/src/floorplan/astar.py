"""Grid shortest paths: 8-connected, optional robot-radius inflation and per-cell cost (the
move_base mock's global planner and the task planner's graph edge lengths use it).

ROS-free. The grid is a boolean obstacle array indexed [row, col]; cells are square with side
`resolution` metres. A diagonal step may not cut the corner of an obstacle (both orthogonal
neighbours must be free), so a path never squeezes between two diagonally touching obstacles.

The grid becomes a sparse graph (one node per cell of the grid padded by a blocked border) and
the search is Dijkstra's algorithm in compiled code (`scipy.sparse.csgraph.dijkstra`; E. W.
Dijkstra, "A note on two problems in connexion with graphs", Numer. Math. 1:269-271, 1959), run
backwards from the goal: it gives the cost from every cell to that goal, a navigation function
as navfn's (K. Konolige, "A gradient method for realtime robot control", IROS 2000), and the path
descends it from the start, through optimal neighbours only, going straight on while that stays
optimal. `astar` keeps its name as the callers' interface; its paths are optimal, as A*'s with
an admissible heuristic.

Graphs are cached by content (obstacles, resolution, robot radius, cell penalty; the last
MAX_GRAPHS) and, per graph, cost fields by their root (the last MAX_FIELDS), so the usual call
patterns build a graph once per map and search once per goal: many place pairs on one map
(`task_planner.graph`), replanning towards one goal from a moving robot (the move_base mock).
`clear_path_cache` empties the cache.
"""
import math
import threading
import zlib
from collections import OrderedDict
from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

SQRT2 = math.sqrt(2.0)
MAX_GRAPHS = 2         # grids (maps, costmaps) whose graphs are kept
MAX_FIELDS = 8         # cost fields kept per graph (one per root)
# the 8 moves (row step, column step), in increasing flat-index offset so CSR rows come sorted
MOVES = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))
FINITE = np.finfo(float).max   # Dijkstra's limit: infinite weights (steps not allowed) stay out
N_MOVES = len(MOVES)
OPPOSITE = tuple(MOVES.index((-dr, -dc)) for dr, dc in MOVES)
STEP = tuple(SQRT2 if dr and dc else 1.0 for dr, dc in MOVES)
TIE_TOLERANCE = 1e-9   # relative: costs this close are equal (sums in another order)

Cell = tuple[int, int]   # (row, col)
# per move: (node offset, slot of the step's weight in the neighbour's row, dr, dc, step)
Move = tuple[int, int, int, int, float]
CacheKey = tuple[tuple[int, ...], float, float, int, int | None]


@dataclass(frozen=True)
class GridPath:
    """Shortest-path result: the (row, col) cells from start to goal and the length [m]."""

    cells: list      # [(row, col), ...] start first, goal last
    length_m: float  # sum of step lengths (1 or sqrt(2) cells) times the resolution [m]


def inflate_obstacles(obstacles: ArrayLike, resolution: float,
                      robot_radius: float) -> NDArray[np.bool_]:
    """Obstacles grown by `robot_radius` [m]: blocked if an obstacle centre lies closer."""
    obstacles = np.asarray(obstacles, dtype=bool)
    if robot_radius <= 0 or not obstacles.any():
        return obstacles.copy()
    free = (~obstacles).astype(np.uint8)
    distance_cells = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    return distance_cells * resolution < robot_radius


def check_cell(name: str, cell: Cell, shape: tuple[int, ...]) -> None:
    """ValueError when `cell` (row, col) lies outside a grid of `shape`."""
    row, col = cell
    if not (0 <= row < shape[0] and 0 <= col < shape[1]):
        raise ValueError(f"A*: {name} cell {cell} lies outside the {shape[0]}x{shape[1]} grid")


def astar(obstacles: ArrayLike, start: Cell, goal: Cell, resolution: float = 1.0,
          robot_radius: float = 0.0, cell_penalty: ArrayLike | None = None) -> GridPath | None:
    """Shortest 8-connected path from `start` to `goal` (row, col) through free cells.

    Args:
        obstacles: bool array (H, W), True = blocked.
        resolution: cell side [m].
        robot_radius: obstacles are inflated by this radius first [m]; 0 = no inflation.
        cell_penalty: optional float array (H, W) >= 0 added to the cost of entering a cell
            [cells of length], as navfn adds costmap cost.
    Returns:
        GridPath, or None when the goal cannot be reached (or start/goal are blocked).
    """
    with _LOCK:
        graph = grid_graph(obstacles, resolution, robot_radius, cell_penalty)
        check_cell("start", start, graph.blocked.shape)
        check_cell("goal", goal, graph.blocked.shape)
        if graph.blocked[start] or graph.blocked[goal]:
            return None
        width = graph.blocked.shape[1] + 2             # nodes of the padded grid
        flat = graph.path((start[0] + 1) * width + start[1] + 1,
                          (goal[0] + 1) * width + goal[1] + 1)
    if flat is None:
        return None
    return _grid_path([(index // width - 1, index % width - 1) for index in flat], resolution)


@dataclass
class GridGraph:
    """One grid as a graph: its blocked cells (after inflation), the reversed step graph and
    the cost fields computed on it so far (root node -> cost of every node to the root)."""

    blocked: np.ndarray
    reverse: csr_matrix   # edge v -> u weighs the step u -> v: step length + penalty of v
    symmetric: bool       # no penalty: every step costs the same both ways
    obstacles: np.ndarray  # the grid it was built from, before inflation
    penalty: np.ndarray | None   # and its cell penalty (or None)
    fields: OrderedDict[int, np.ndarray] = field(default_factory=OrderedDict)

    def holds(self, obstacles: NDArray[np.bool_], penalty: NDArray[np.float64] | None) -> bool:
        """True when the graph was built from exactly these arrays."""
        if penalty is None or self.penalty is None:
            return penalty is self.penalty and np.array_equal(obstacles, self.obstacles)
        return np.array_equal(obstacles, self.obstacles) and np.array_equal(penalty, self.penalty)

    def cost_to(self, root: int) -> NDArray[np.float64]:
        """Cost [cells of length] from every node to `root` (inf where it cannot be reached)."""
        if root in self.fields:
            self.fields.move_to_end(root)
            return self.fields[root]
        self.fields[root] = dijkstra(self.reverse, directed=True, indices=root, limit=FINITE)
        if len(self.fields) > MAX_FIELDS:
            self.fields.popitem(last=False)
        return self.fields[root]

    def path(self, start: int, goal: int) -> list[int] | None:
        """Flat node indices of a shortest path start -> goal, or None if there is none. When
        steps cost the same both ways a field rooted at the start serves too, and a new field is
        rooted at the start (callers measuring many pairs repeat the start: i < j loops)."""
        if self.symmetric and goal not in self.fields:
            backwards = self.descend(self.cost_to(start), goal, start)
            return None if backwards is None else backwards[::-1]
        return self.descend(self.cost_to(goal), start, goal)

    def descend(self, cost: NDArray[np.float64], node: int, root: int) -> list[int] | None:
        """Nodes from `node` down the cost-to-`root` field to `root` (navfn's descent on its
        potential, on the grid): each step goes to a neighbour through which the cost is
        optimal, keeping the previous direction when it is one of them, else the direction
        closest to the straight line to the root. None when `node` cannot reach `root`."""
        if not math.isfinite(cost[node]):
            return None
        width = self.blocked.shape[1] + 2
        weights, costs = memoryview(self.reverse.data), cost.data   # Python floats, fast
        moves: list[Move] = [
            (dr * width + dc, OPPOSITE[k] + N_MOVES * (dr * width + dc), dr, dc, STEP[k])
            for k, (dr, dc) in enumerate(MOVES)]
        root_row, root_col = divmod(root, width)
        nodes, move = [node], None
        while node != root:
            limit = costs[node] + TIE_TOLERANCE * max(1.0, costs[node])
            if move is not None:                      # keep going straight when optimal
                offset, slot = move[0], move[1]
                if weights[N_MOVES * node + slot] + costs[node + offset] <= limit:
                    node += offset
                    nodes.append(node)
                    continue
            row, col = divmod(node, width)
            best: tuple[float, Move] | None = None
            for candidate in moves:
                offset, slot, dr, dc, step = candidate
                if weights[N_MOVES * node + slot] + costs[node + offset] > limit:
                    continue                  # not optimal, not allowed, or unreachable
                score = ((root_row - row) * dr + (root_col - col) * dc) / step
                if best is None or score > best[0]:
                    best = (score, candidate)
            if best is None:   # a finite cost is reached through some optimal neighbour
                raise RuntimeError(f"A*: no optimal step from node {node} towards {root}")
            move = best[1]
            node += move[0]
            nodes.append(node)
        return nodes


def grid_graph(obstacles: ArrayLike, resolution: float = 1.0, robot_radius: float = 0.0,
               cell_penalty: ArrayLike | None = None) -> GridGraph:
    """The cached GridGraph of a grid, built on first use (obstacles inflated by
    `robot_radius`); ValueError for a cell penalty of another shape or below 0."""
    obstacles = np.asarray(obstacles, dtype=bool)
    penalty: NDArray[np.float64] | None = None
    if cell_penalty is not None:
        penalty = np.asarray(cell_penalty, dtype=float)
        if penalty.shape != obstacles.shape or (penalty < 0).any():
            raise ValueError(f"A*: cell_penalty must be >= 0 with shape {obstacles.shape}")
    key = _cache_key(obstacles, resolution, robot_radius, penalty)
    cached = _GRAPHS.get(key)
    if cached is not None and cached.holds(obstacles, penalty):
        _GRAPHS.move_to_end(key)
        return cached
    blocked = inflate_obstacles(obstacles, resolution, robot_radius)
    graph = GridGraph(blocked, reverse_step_graph(blocked, penalty), penalty is None,
                      obstacles.copy(), None if penalty is None else penalty.copy())
    _GRAPHS[key] = graph
    _GRAPHS.move_to_end(key)
    if len(_GRAPHS) > MAX_GRAPHS:
        _GRAPHS.popitem(last=False)
    return graph


def reverse_step_graph(blocked: NDArray[np.bool_],
                       penalty: NDArray[np.float64] | None = None) -> csr_matrix:
    """Sparse graph of the allowed steps on the grid padded by one blocked cell, reversed: node
    (r + 1) * (W + 2) + c + 1 is cell (r, c), and for each step u -> v between free cells
    (diagonals only when both corner cells are free) the edge v -> u weighs the step length (1
    or sqrt(2)) plus `penalty[v]`. Every node lists all 8 neighbours; a step that is not
    allowed weighs infinity, which Dijkstra never takes, so the arrays need no compaction.
    Dijkstra from a goal on it yields costs and next steps towards that goal."""
    height, width = blocked.shape
    free = np.pad(~blocked, 1, constant_values=False)
    padded_width = width + 2
    nodes = free.size

    def shifted(dr: int, dc: int) -> NDArray[np.bool_]:
        return free[1 + dr:height + 1 + dr, 1 + dc:width + 1 + dc]

    weights = np.full((height + 2, padded_width, len(MOVES)), np.inf)
    inner = weights[1:-1, 1:-1]
    cost = np.zeros((height, width)) if penalty is None else penalty
    for k, (dr, dc) in enumerate(MOVES):
        allowed = shifted(0, 0) & shifted(dr, dc)
        if dr and dc:
            allowed &= shifted(dr, 0) & shifted(0, dc)
        step = SQRT2 if dr and dc else 1.0
        np.add(cost, step, out=inner[:, :, k], where=allowed)
    offsets = np.array([dr * padded_width + dc for dr, dc in MOVES], dtype=np.int32)
    indices = np.arange(nodes, dtype=np.int32)[:, None] + offsets
    np.clip(indices, 0, nodes - 1, out=indices)       # border nodes: only infinite weights
    indptr = np.arange(0, len(MOVES) * nodes + 1, len(MOVES), dtype=np.int32)
    return csr_matrix((weights.ravel(), indices.ravel(), indptr), shape=(nodes, nodes))


def clear_path_cache() -> None:
    """Forget every cached graph and cost field."""
    with _LOCK:
        _GRAPHS.clear()


# cache key -> GridGraph, least recently used first
_GRAPHS: OrderedDict[CacheKey, GridGraph] = OrderedDict()
_LOCK = threading.Lock()


def _cache_key(obstacles: NDArray[np.bool_], resolution: float, robot_radius: float,
               penalty: NDArray[np.float64] | None) -> CacheKey:
    """A cheap content key (CRC-32 of the arrays); GridGraph.holds confirms a hit exactly."""
    key = (obstacles.shape, float(resolution), float(robot_radius),
           zlib.crc32(np.ascontiguousarray(obstacles).view(np.uint8).data))
    if penalty is None:
        return key + (None,)
    return key + (zlib.crc32(np.ascontiguousarray(penalty).view(np.uint8).data),)


def _grid_path(cells: list[Cell], resolution: float) -> GridPath:
    length = sum(SQRT2 if (a[0] != b[0] and a[1] != b[1]) else 1.0
                 for a, b in zip(cells, cells[1:]))
    return GridPath(cells=cells, length_m=length * resolution)
