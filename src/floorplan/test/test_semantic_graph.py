
import pytest

from floorplan.semantic_graph import GraphError, load_graph
from tamp_resources import resource

MAPS = resource("maps")


def write_graph(tmp_path, text):
    path = tmp_path / "g.graph.yaml"
    path.write_text(text)
    return path


def test_household_graph_places_and_edges():
    graph = load_graph(MAPS / "household.graph.yaml")
    assert graph.map_file == "household.yaml"
    assert graph.place_ids()["charging_place"] == 0
    assert graph.place("alley").pose == pytest.approx((3.4, 7.0, 1.5708))
    assert ("living_room", "welcome") in graph.edges
    with pytest.raises(KeyError, match="no place named 'garage'"):
        graph.place("garage")


def test_missing_key_names_the_node(tmp_path):
    path = write_graph(tmp_path, "nodes:\n  - {id: 0, name: a, pose: [0, 0, 0]}\n")
    with pytest.raises(GraphError, match="node 0 misses region"):
        load_graph(path)


def test_edge_to_an_unknown_place_is_refused(tmp_path):
    path = write_graph(tmp_path, "nodes:\n  - {id: 0, name: a, pose: [0, 0, 0], region: []}\n"
                                 "edges:\n  - [a, b]\n")
    with pytest.raises(GraphError, match=r"edge \[a, b\] names an unknown place"):
        load_graph(path)


def test_duplicate_names_are_refused(tmp_path):
    path = write_graph(tmp_path, "nodes:\n  - {id: 0, name: a, pose: [0, 0, 0], region: []}\n"
                                 "  - {id: 1, name: a, pose: [1, 0, 0], region: []}\n")
    with pytest.raises(GraphError, match="unique"):
        load_graph(path)


def test_unreadable_file_names_the_file(tmp_path):
    with pytest.raises(GraphError, match="missing.graph.yaml: cannot read graph"):
        load_graph(tmp_path / "missing.graph.yaml")
