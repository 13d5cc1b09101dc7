"""Shared fixtures: small hand-made graphs and instruction factories."""
import pytest
from planner_factories import POOL_BACKENDS

from task_planner.graph import graph_from_edges
from task_planner.pg_cluster import PgCluster


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


@pytest.fixture(scope="session")
def pg_cluster():
    """One throw-away PostgreSQL server for the test session, on 127.0.0.1 (no server programs:
    the tests fail and say so; scripts/setup installs them)."""
    with PgCluster() as cluster:
        yield cluster


@pytest.fixture(params=POOL_BACKENDS)
def pool_url(request, tmp_path):
    """Where a new, empty fleet pool is: an SQLite file, or a new database on the session's
    PostgreSQL server (parametrize "pool_url" with indirect=True to choose)."""
    if request.param == "sqlite":
        return str(tmp_path / "pool.sqlite")
    return request.getfixturevalue("pg_cluster").create_database()
