"""Shared fixtures of the bringup tests."""
import pytest

from task_planner.graph import graph_from_edges


@pytest.fixture
def line_graph():
    """A -1- B -2- C -3- D (metres)."""
    return graph_from_edges("ABCD", [("A", "B", 1.0), ("B", "C", 2.0), ("C", "D", 3.0)])
