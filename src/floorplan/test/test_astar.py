import heapq
import math

import numpy as np
import pytest

from floorplan.astar import astar, clear_path_cache, inflate_obstacles
from floorplan.tools.astar_reference import reference_astar

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


def dijkstra_length(obstacles, start, goal, penalty=None):
    """Independent reference: plain Dijkstra with the same move rules, on (row, col) tuples;
    entering a cell costs its `penalty` on top of the step length."""
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
                new = dist + (R2 if dr and dc else 1.0) + (0.0 if penalty is None
                                                            else penalty[nr, nc])
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


def path_cost(cells, penalty=None):
    """Cost of a returned path: steps (1 or sqrt 2) plus the penalty of each entered cell."""
    cost = 0.0
    for (r0, c0), (r1, c1) in zip(cells, cells[1:]):
        cost += (R2 if r0 != r1 and c0 != c1 else 1.0) + (0.0 if penalty is None
                                                          else penalty[r1, c1])
    return cost


def assert_legal_steps(obstacles, cells):
    """Every cell free, every step to one of the 8 neighbours, no diagonal cuts a corner."""
    for (r0, c0), (r1, c1) in zip(cells, cells[1:]):
        assert max(abs(r1 - r0), abs(c1 - c0)) == 1
        assert not obstacles[r1, c1]
        if r0 != r1 and c0 != c1:
            assert not obstacles[r0, c1] and not obstacles[r1, c0]


def test_cell_penalty_matches_independent_dijkstra_on_random_grids():
    rng = np.random.default_rng(11)
    for _ in range(40):
        obstacles = rng.random((10, 13)) < 0.25
        penalty = rng.random((10, 13)) * rng.choice([0.0, 0.5, 3.0])
        obstacles[0, 0] = obstacles[9, 12] = False
        expected = dijkstra_length(obstacles, (0, 0), (9, 12), penalty)
        path = astar(obstacles, (0, 0), (9, 12), 0.1, cell_penalty=penalty)
        if expected is None:
            assert path is None
            continue
        assert path.cells[0] == (0, 0) and path.cells[-1] == (9, 12)
        assert_legal_steps(obstacles, path.cells)
        assert path_cost(path.cells, penalty) == pytest.approx(expected)
        assert path.length_m == pytest.approx(0.1 * path_cost(path.cells))


def test_penalty_steers_the_path_around_costly_cells():
    obstacles = np.zeros((3, 7), bool)
    penalty = np.zeros((3, 7))
    penalty[1, 1:6] = 10.0           # the straight row 1 is costly: go by row 0 or 2
    path = astar(obstacles, (1, 0), (1, 6), cell_penalty=penalty)
    assert all(row != 1 for row, _ in path.cells[1:-1])
    assert path.length_m == pytest.approx(4 + 2 * R2)


def test_bad_cell_penalty_is_a_clear_error():
    with pytest.raises(ValueError, match="cell_penalty"):
        astar(np.zeros((3, 3), bool), (0, 0), (2, 2), cell_penalty=np.zeros((2, 3)))
    with pytest.raises(ValueError, match="cell_penalty"):
        astar(np.zeros((3, 3), bool), (0, 0), (2, 2), cell_penalty=-np.ones((3, 3)))


def test_cached_graph_follows_an_array_changed_in_place():
    clear_path_cache()
    obstacles = np.zeros((5, 5), bool)
    assert astar(obstacles, (2, 0), (2, 4)).length_m == pytest.approx(4)
    obstacles[:4, 2] = True          # same array object, new wall with a gap at the bottom
    path = astar(obstacles, (2, 0), (2, 4))
    assert path.length_m == pytest.approx(dijkstra_length(obstacles, (2, 0), (2, 4)))
    assert (4, 2) in path.cells
    penalty = np.zeros((5, 5))
    free_cost = path_cost(astar(obstacles, (2, 0), (2, 4), cell_penalty=penalty).cells)
    penalty[4, 2] = 5.0              # the gap now costs 5 more
    assert path_cost(astar(obstacles, (2, 0), (2, 4), cell_penalty=penalty).cells, penalty) \
        == pytest.approx(free_cost + 5.0)


def test_both_directions_return_start_first_and_legal_steps():
    clear_path_cache()
    rng = np.random.default_rng(3)
    obstacles = rng.random((15, 15)) < 0.2
    obstacles[0, 0] = obstacles[14, 14] = False
    expected = dijkstra_length(obstacles, (14, 14), (0, 0))
    assert expected is not None
    there = astar(obstacles, (0, 0), (14, 14))     # costs to (0, 0), descended from the goal
    back = astar(obstacles, (14, 14), (0, 0))      # the same costs, descended from the start
    for path, start, goal in ((there, (0, 0), (14, 14)), (back, (14, 14), (0, 0))):
        assert path.cells[0] == start and path.cells[-1] == goal
        assert_legal_steps(obstacles, path.cells)
        assert path.length_m == pytest.approx(expected)


def test_same_start_and_goal_is_a_one_cell_path():
    path = astar(np.zeros((3, 3), bool), (1, 1), (1, 1))
    assert path.cells == [(1, 1)] and path.length_m == 0.0


def test_same_lengths_as_the_reference_astar_with_inflation_and_penalty():
    rng = np.random.default_rng(5)
    obstacles = rng.random((30, 40)) < 0.08
    penalty = rng.random((30, 40))
    free = np.argwhere(~inflate_obstacles(obstacles, 0.1, 0.12))
    for _ in range(20):
        start, goal = (tuple(free[i]) for i in rng.integers(len(free), size=2))
        for kwargs in ({"robot_radius": 0.12}, {"cell_penalty": penalty}):
            new = astar(obstacles, start, goal, 0.1, **kwargs)
            old = reference_astar(obstacles, start, goal, 0.1, **kwargs)
            assert (new is None) == (old is None)
            if new is not None:
                assert new.length_m == pytest.approx(old.length_m)


def test_open_grid_path_turns_once():
    # 2 diagonal and 4 straight steps in any order are optimal; the descent keeps its direction
    path = astar(np.zeros((5, 9), bool), (0, 0), (2, 6))
    moves = [(b[0] - a[0], b[1] - a[1]) for a, b in zip(path.cells, path.cells[1:])]
    assert sorted(moves) == [(0, 1)] * 4 + [(1, 1)] * 2
    assert sum(m != n for m, n in zip(moves, moves[1:])) == 1
