"""Shared fixtures: small hand-made graphs and instruction factories."""
import pytest

from task_planner.graph import graph_from_edges


@pytest.fixture
def line_graph():
    """A -1- B -2- C -3- D (metres)."""
    return graph_from_edges("ABCD", [("A", "B", 1.0), ("B", "C", 2.0), ("C", "D", 3.0)])


@pytest.fixture
def star_graph():
    """Hub H with leaves L1, L2, L3 at 4 m each."""
    return graph_from_edges(["H", "L1", "L2", "L3"],
                            [("H", "L1", 4.0), ("H", "L2", 4.0), ("H", "L3", 4.0)])


@pytest.fixture
def posed_line_graph():
    """A -1- B -2- C -3- D (metres) on the x axis, every place facing east."""
    return graph_from_edges("ABCD", [("A", "B", 1.0), ("B", "C", 2.0), ("C", "D", 3.0)],
                            poses=[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (3.0, 0.0, 0.0),
                                   (6.0, 0.0, 0.0)])
