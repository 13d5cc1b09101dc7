"""Semantic topological graphs of maps (`maps/<map>.graph.yaml`): named places and their links."""
from dataclasses import dataclass, field
from pathlib import Path

import yaml


class GraphError(ValueError):
    """A graph file that cannot be used; the message names the file and the problem."""


@dataclass
class Place:
    id: int
    name: str
    pose: tuple            # (x [m], y [m], yaw [rad]) in the map frame
    region: list           # polygon [[x, y], ...] [m]


@dataclass
class SemanticGraph:
    map_file: str
    places: list
    edges: list = field(default_factory=list)   # [(name, name)]

    def place(self, name: str) -> Place:
        for place in self.places:
            if place.name == name:
                return place
        raise KeyError(f"no place named {name!r} (places: {[p.name for p in self.places]})")

    def place_ids(self) -> dict[str, int]:
        """{place name: node id}."""
        return {place.name: place.id for place in self.places}


def load_graph(path: str | Path) -> SemanticGraph:
    """Read a `<map>.graph.yaml`; GraphError names the file and what is wrong."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise GraphError(f"{path}: cannot read graph: {error}") from error
    if not isinstance(data, dict) or "nodes" not in data:
        raise GraphError(f"{path}: expected a mapping with 'nodes'")
    places = []
    for i, node in enumerate(data["nodes"]):
        missing = [k for k in ("id", "name", "pose", "region") if k not in node]
        if missing:
            raise GraphError(f"{path}: node {i} misses {', '.join(missing)}")
        if len(node["pose"]) != 3:
            raise GraphError(f"{path}: node {node['name']!r} pose must be [x, y, yaw]")
        places.append(Place(int(node["id"]), str(node["name"]),
                            tuple(float(v) for v in node["pose"]),
                            [[float(x), float(y)] for x, y in node["region"]]))
    names = {p.name for p in places}
    if len(names) != len(places) or len({p.id for p in places}) != len(places):
        raise GraphError(f"{path}: place names and ids must be unique")
    edges = [tuple(e) for e in data.get("edges", [])]
    for a, b in edges:
        if a not in names or b not in names:
            raise GraphError(f"{path}: edge [{a}, {b}] names an unknown place")
    return SemanticGraph(str(data.get("map", "")), places, edges)
