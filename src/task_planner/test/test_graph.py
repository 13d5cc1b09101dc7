import shutil

import numpy as np
import pytest

from task_planner.graph import GraphError, floyd_warshall, graph_from_edges, load_graph
from tamp_resources import resource

MAPS = resource("maps")
INF = np.inf


def test_floyd_warshall_against_hand_solved_graph():
    # 0-1: 4, 0-2: 1, 2-1: 2, 1-3: 5, 2-3: 8.  Hand-solved shortest paths:
    # 0->1 = 3 (via 2), 0->3 = 8 (0-2-1-3), 2->3 = 7 (2-1-3)
    adjacency = np.zeros((4, 4))
    for i, j, w in [(0, 1, 4), (0, 2, 1), (2, 1, 2), (1, 3, 5), (2, 3, 8)]:
        adjacency[i, j] = adjacency[j, i] = w
    distances, hops = floyd_warshall(adjacency)
    expected = np.array([[0, 3, 1, 8],
                         [3, 0, 2, 5],
                         [1, 2, 0, 7],
                         [8, 5, 7, 0]], float)
    assert distances == pytest.approx(expected)
    assert hops[0, 3] == 2 and hops[2, 3] == 1 and hops[3, 0] == 1


def test_path_follows_next_hops(line_graph):
    assert line_graph.path(0, 3) == [0, 1, 2, 3]
    assert line_graph.path(3, 1) == [3, 2, 1]
    assert line_graph.shortest[0, 3] == pytest.approx(6.0)


def test_disconnected_graph_names_the_places():
    with pytest.raises(GraphError, match="disconnected.*'A'.*'C'"):
        graph_from_edges("ABC", [("A", "B", 1.0)])


def test_unknown_place_in_edge():
    with pytest.raises(GraphError, match="unknown place 'Z'"):
        graph_from_edges("AB", [("A", "Z", 1.0)])


def test_household_edges_are_astar_lengths_and_cached(tmp_path):
    graph = load_graph(MAPS / "household.graph.yaml", robot_radius=0.25, cache_dir=tmp_path)
    assert graph.size == 7 and len(graph.edges()) == 6
    for i, j, length in graph.edges():
        straight = np.hypot(*(graph.poses[i][:2] - graph.poses[j][:2]))
        assert straight - 0.1 <= length <= 2.0 * straight + 1.0  # grid path: >= straight line
    assert len(list(tmp_path.glob("*.json"))) == 1
    again = load_graph(MAPS / "household.graph.yaml", robot_radius=0.25, cache_dir=tmp_path)
    assert np.array_equal(again.adjacency, graph.adjacency)


def test_changed_map_is_measured_again(tmp_path):
    for name in ("household.graph.yaml", "household.yaml", "household.pgm"):
        shutil.copy(MAPS / name, tmp_path / name)
    cache = tmp_path / "cache"
    before = load_graph(tmp_path / "household.graph.yaml", cache_dir=cache)
    pgm = (tmp_path / "household.pgm").read_bytes()
    header_end = len(pgm) - 136 * 236          # P5 binary: header, then one byte per pixel
    pixels = bytearray(pgm[header_end:])
    # a wall inside the living room across the line from living_room (2.2, 2.0) to the door to
    # welcome (x = 4.0 m, y = 0.6 .. 2.4 m): x = 3.0 m (col 60), y = 0 .. 2.6 m; image row 0 is
    # the top, so row = 235 - y / 0.05
    for y in np.arange(0.0, 2.6, 0.05):
        row = 235 - int(round(y / 0.05))
        for col in (59, 60, 61):
            pixels[row * 136 + col] = 0
    (tmp_path / "household.pgm").write_bytes(pgm[:header_end] + bytes(pixels))
    after = load_graph(tmp_path / "household.graph.yaml", cache_dir=cache)
    living, welcome = before.index("living_room"), before.index("welcome")
    assert after.adjacency[living, welcome] > before.adjacency[living, welcome] + 0.5
    assert len(list(cache.glob("*.json"))) == 2
