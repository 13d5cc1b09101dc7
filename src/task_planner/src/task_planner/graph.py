"""Topological graph of the home (thesis 000 §4.2.2-4.2.3, Fig. 4-4, Fig. 4-7).

Nodes are semantic places from `maps/<map>.graph.yaml`; an edge joins two directly connected
places and weighs the A* path length between their poses on the occupancy grid (the move_base
mock's planner). Lengths are cached per (map, graph, robot radius) content hash and recomputed
when any of them changes. The planners use the adjacency matrix and the all-pairs shortest-path
matrix of Floyd-Warshall.
"""
import hashlib
import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from floorplan.semantic_graph import GraphError as SemanticGraphError
from floorplan.semantic_graph import load_graph as load_semantic_graph


class GraphError(ValueError):
    """A graph file or graph that cannot be planned on; the message names the offending item."""


@dataclass(frozen=True)
class TopologicalGraph:
    """Places and weighted edges; `adjacency[i, j]` = edge length [m], 0 = no edge (Fig. 4-7b)."""

    names: tuple[str, ...]     # place names, index = node id
    adjacency: np.ndarray      # (V, V) edge lengths [m]; 0 = no edge
    poses: np.ndarray | None = None  # (V, 3) x, y, yaw in the map frame [m, m, rad], if known
    # derived in __post_init__, not arguments
    shortest: np.ndarray = field(init=False, repr=False, compare=False)
    next_hop: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        distances, hops = floyd_warshall(self.adjacency)
        unreachable = np.argwhere(~np.isfinite(distances))
        if len(unreachable):
            i, j = unreachable[0]
            raise GraphError(f"graph is disconnected: no path from '{self.names[i]}' "
                             f"to '{self.names[j]}'")
        object.__setattr__(self, "shortest", distances)  # (V, V) shortest path lengths [m]
        object.__setattr__(self, "next_hop", hops)       # (V, V) first node on the path i -> j

    @property
    def size(self) -> int:
        return len(self.names)

    def edges(self) -> list[tuple[int, int, float]]:
        """[(i, j, length_m)] with i < j."""
        rows, cols = np.nonzero(np.triu(self.adjacency))
        return [(int(i), int(j), float(self.adjacency[i, j])) for i, j in zip(rows, cols)]

    def pose(self, node: int) -> np.ndarray:
        """(x, y, yaw) of `node` in the map frame [m, m, rad]; GraphError when the graph has no
        poses."""
        if self.poses is None:
            raise GraphError(f"the graph has no poses: where place '{self.names[node]}' is is "
                             "not known")
        return self.poses[node]

    def neighbours(self, node: int) -> list[int]:
        return [int(n) for n in np.flatnonzero(self.adjacency[node])]

    def path(self, source: int, target: int) -> list[int]:
        """Node sequence of a shortest path, both ends included."""
        nodes = [source]
        while nodes[-1] != target:
            nodes.append(int(self.next_hop[nodes[-1], target]))
        return nodes

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise GraphError(f"unknown place '{name}' (known: {', '.join(self.names)})") from None


def adjacency_matrix(size: int, edges: Iterable[tuple[int, int, float]]) -> np.ndarray:
    """Fig. 4-7(b): symmetric matrix of edge lengths from [(i, j, length_m)]; 0 = no edge."""
    matrix = np.zeros((size, size))
    for i, j, length in edges:
        if i == j or not length > 0:
            raise GraphError(f"edge ({i}, {j}): need two different nodes and a length > 0, "
                             f"got {length}")
        matrix[i, j] = matrix[j, i] = length
    return matrix


def floyd_warshall(adjacency: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """§4.2.3, Fig. 4-7(c): all-pairs shortest path lengths and first-hop matrix.

    Returns (distances, next_hop); distances are inf and next_hop -1 between disconnected nodes.
    """
    size = len(adjacency)
    distances = np.where(adjacency > 0, adjacency, np.inf)
    np.fill_diagonal(distances, 0.0)
    hops = np.where(np.isfinite(distances), np.arange(size)[None, :], -1)
    for k in range(size):
        through = distances[:, k:k + 1] + distances[k:k + 1, :]
        better = through < distances
        distances = np.where(better, through, distances)
        hops = np.where(better, hops[:, k:k + 1], hops)
    return distances, hops


def graph_from_edges(names: Iterable[str],
                     edges: Iterable[tuple[str | int, str | int, float]],
                     poses: np.ndarray | None = None) -> TopologicalGraph:
    """Build a graph from place names and [(name_a, name_b, length_m)] or index triples."""
    names = tuple(names)
    index: dict[str | int, int] = {name: i for i, name in enumerate(names)}
    resolved: list[tuple[Any, Any, float]] = []
    for a, b, length in edges:
        for end in (a, b):
            if not (end in index or (isinstance(end, int) and 0 <= end < len(names))):
                raise GraphError(f"edge ({a}, {b}): unknown place '{end}'")
        resolved.append((index.get(a, a), index.get(b, b), float(length)))
    return TopologicalGraph(names, adjacency_matrix(len(names), resolved), poses)


def default_cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "tamp_ws" / "graph_edges"


def load_graph(graph_path: str | Path, robot_radius: float = 0.25,
               cache_dir: str | Path | None = None) -> TopologicalGraph:
    """Read `<map>.graph.yaml`; edge lengths by A* on its occupancy map (cached).

    Args:
        graph_path: semantic graph YAML with `map`, `nodes` (id, name, pose) and `edges`.
        robot_radius: obstacle inflation for A* [m].
        cache_dir: where measured lengths are kept; default ~/.cache/tamp_ws/graph_edges.
    """
    graph_path = Path(graph_path)
    spec = _read_graph_spec(graph_path)
    map_path = graph_path.parent / spec["map"]
    key = _content_hash(graph_path, map_path, robot_radius)
    cache_file = Path(cache_dir or default_cache_dir()) / f"{key}.json"
    names = tuple(node["name"] for node in spec["nodes"])
    poses = np.array([node["pose"] for node in spec["nodes"]], dtype=float)
    if cache_file.is_file():
        lengths = json.loads(cache_file.read_text())["lengths_m"]
    else:
        lengths = measure_edge_lengths(map_path, poses, spec["edge_pairs"], robot_radius)
        cache_file.parent.mkdir(parents=True, exist_ok=True)
        cache_file.write_text(json.dumps({"graph": str(graph_path), "lengths_m": lengths}))
    edges = [(i, j, length) for (i, j), length in zip(spec["edge_pairs"], lengths)]
    return TopologicalGraph(names, adjacency_matrix(len(names), edges), poses)


def measure_edge_lengths(map_path: Path, poses: np.ndarray, pairs: Sequence[tuple[int, int]],
                         robot_radius: float) -> list[float]:
    """A* path length [m] between the poses of each pair of places on the occupancy grid."""
    from floorplan.astar import astar
    from floorplan.occupancy_map import load_map

    grid = load_map(map_path)
    blocked = grid.occupied_mask()
    lengths = []
    for i, j in pairs:
        cells = [(int(row), int(col)) for row, col in
                 (grid.world_to_cell(*poses[k][:2]) for k in (i, j))]
        path = astar(blocked, cells[0], cells[1], grid.resolution, robot_radius)
        if path is None:
            raise GraphError(f"{map_path}: no A* path between places {i} and {j} "
                             f"(robot radius {robot_radius} m)")
        lengths.append(path.length_m)
    return lengths


def place_ids(graph_path: str | Path) -> dict[str, int]:
    """{place name: node id} of `<map>.graph.yaml`, ids in file order as `load_graph` numbers
    them, without measuring edges; GraphError for a file the planner refuses."""
    spec = _read_graph_spec(Path(graph_path))
    return {node["name"]: index for index, node in enumerate(spec["nodes"])}


def _content_hash(graph_path: Path, map_path: Path, robot_radius: float) -> str:
    digest = hashlib.sha256(f"radius={robot_radius}".encode())
    map_meta = yaml.safe_load(map_path.read_text())
    for path in (graph_path, map_path, map_path.parent / map_meta["image"]):
        digest.update(path.read_bytes())
    return digest.hexdigest()[:32]


def _read_graph_spec(graph_path: Path) -> dict[str, Any]:
    """The graph file through floorplan's reader; the planner also needs ids 0..n-1 in file
    order."""
    try:
        semantic = load_semantic_graph(graph_path)
    except SemanticGraphError as error:
        raise GraphError(str(error)) from error
    for position, place in enumerate(semantic.places):
        if place.id != position:
            raise GraphError(f"{graph_path}: node #{position} ({place.name}) needs id {position}")
    if not semantic.map_file:
        raise GraphError(f"{graph_path}: needs 'map' (the occupancy map the edges are measured on)")
    index = {place.name: place.id for place in semantic.places}
    return {"map": semantic.map_file,
            "nodes": [{"name": place.name, "pose": place.pose} for place in semantic.places],
            "edge_pairs": [(index[a], index[b]) for a, b in semantic.edges]}
