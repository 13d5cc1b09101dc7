import heapq
import math

import numpy as np
import pytest

from floorplan.astar import astar, inflate_obstacles

R2 = math.sqrt(2.0)


def grid(rows):
    """'#' = obstacle, '.' = free; the first text row is grid row 0."""
    return np.array([[ch == "#" for ch in row] for row in rows])


def test_open_grid_diagonal_length():
    path = astar(np.zeros((5, 5), bool), (0, 0), (4, 4), resolution=0.05)
    assert path.length_m == pytest.approx(4 * R2 * 0.05)
    assert path.cells[0] == (0, 0) and path.cells[-1] == (4, 4) and len(path.cells) == 5


def test_mixed_moves_length():
    path = astar(np.zeros((3, 5), bool), (0, 0), (2, 4))
    assert path.length_m == pytest.approx(2 * R2 + 2)


def test_wall_with_gap_no_corner_cutting():
    obstacles = grid(["..#..",
                      "..#..",
                      "..#..",
                      "..#..",
                      "....."])
    path = astar(obstacles, (0, 0), (0, 4), resolution=1.0)
    # hand-solved: (0,0)-(1,1) diag, straight to (4,1), (4,2), (4,3), diag (3,4), up to (0,4)
    assert path.length_m == pytest.approx(8 + 2 * R2)
    assert (4, 2) in path.cells
    assert all(not obstacles[c] for c in path.cells)


def test_diagonal_squeeze_between_obstacles_is_refused():
    obstacles = grid([".#",
                      "#."])
    assert astar(obstacles, (0, 0), (1, 1)) is None


def test_enclosed_goal_is_unreachable():
    obstacles = grid([".....",
                      ".###.",
                      ".#.#.",
                      ".###.",
                      "....."])
    assert astar(obstacles, (0, 0), (2, 2)) is None


def test_blocked_start_or_goal():
    obstacles = grid(["#.", ".."])
    assert astar(obstacles, (0, 0), (1, 1)) is None
    assert astar(obstacles, (1, 1), (0, 0)) is None


def test_outside_cell_is_a_clear_error():
    with pytest.raises(ValueError, match="goal cell"):
        astar(np.zeros((3, 3), bool), (0, 0), (3, 0))


def test_inflation_closes_a_narrow_corridor():
    obstacles = np.ones((7, 9), bool)
    obstacles[3, :] = False          # a corridor one cell wide, walls at 1 cell from its centre
    assert astar(obstacles, (3, 0), (3, 8), 0.1).length_m == pytest.approx(0.8)
    assert astar(obstacles, (3, 0), (3, 8), 0.1, robot_radius=0.15) is None
    obstacles[2:5, :] = False        # three cells wide: the centre row keeps 0.2 m clearance
    path = astar(obstacles, (3, 0), (3, 8), 0.1, robot_radius=0.15)
    assert path.length_m == pytest.approx(0.8)
    assert {row for row, _ in path.cells} == {3}


def test_inflate_marks_cells_within_radius():
    obstacles = np.zeros((5, 5), bool)
    obstacles[2, 2] = True
    grown = inflate_obstacles(obstacles, 1.0, 1.2)
    # radius 1.2: the obstacle and its 4 orthogonal neighbours (at 1), not the diagonals (1.41)
    assert grown.sum() == 5 and grown[1, 2] and not grown[1, 1]
    assert inflate_obstacles(obstacles, 1.0, 1.5).sum() == 9


def dijkstra_length(obstacles, start, goal):
    """Independent reference: plain Dijkstra with the same move rules, on (row, col) tuples."""
    rows, cols = obstacles.shape
    best = {start: 0.0}
    queue = [(0.0, start)]
    while queue:
        dist, (r, c) = heapq.heappop(queue)
        if (r, c) == goal:
            return dist
        if dist > best[(r, c)]:
            continue
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (dr, dc) == (0, 0) or not (0 <= nr < rows and 0 <= nc < cols):
                    continue
                corner = dr and dc and (obstacles[r + dr, c] or obstacles[r, c + dc])
                if obstacles[nr, nc] or corner:
                    continue
                new = dist + (R2 if dr and dc else 1.0)
                if new < best.get((nr, nc), math.inf):
                    best[(nr, nc)] = new
                    heapq.heappush(queue, (new, (nr, nc)))
    return None


def test_matches_independent_dijkstra_on_random_grids():
    rng = np.random.default_rng(7)
    for _ in range(40):
        obstacles = rng.random((12, 15)) < 0.3
        obstacles[0, 0] = obstacles[11, 14] = False
        expected = dijkstra_length(obstacles, (0, 0), (11, 14))
        path = astar(obstacles, (0, 0), (11, 14))
        if expected is None:
            assert path is None
        else:
            assert path.length_m == pytest.approx(expected)
