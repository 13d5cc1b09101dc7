"""scripts/bench_overdue's logic: the Poisson requests, the waits of one run, the table."""
import pytest
from tamp_resources import resource

from task_planner.graph import load_graph
from task_planner.instruction import HUMAN, Instruction
from task_planner.reward import load_priorities
from task_planner.robot_functions import load_robot_functions
from task_planner.tools import bench_overdue as bench

GRAPH = load_graph(resource("maps", "household.graph.yaml"))
PRIORITIES = load_priorities(resource("config", "priorities.yaml"))
FUNCTIONS = load_robot_functions(resource("config", "robot_functions.yaml"))


def test_poisson_requests_are_peoples_and_repeat_with_their_seed():
    first = bench.poisson_requests(3, 40.0, 400.0, GRAPH, PRIORITIES, FUNCTIONS)
    assert first == bench.poisson_requests(3, 40.0, 400.0, GRAPH, PRIORITIES, FUNCTIONS)
    assert 3 <= len(first) <= 30 and all(0 < r.start_time <= 400.0 for r in first)
    assert all(r.type == HUMAN and FUNCTIONS[r.function].name not in bench.OWN_FUNCTIONS
               and r.duration == int(FUNCTIONS[r.function].duration_s) for r in first)


def test_a_request_where_the_robot_stands_is_served_at_once():
    """The executor starts at node 0; a request there launched at 5 s waits 0 s."""
    request = Instruction(id=1, gamma=3.0, beta=0.94, destination=0, start_time=5.0,
                          duration=10, function=1, type=HUMAN)
    waits = bench.waits([request], "oldest", GRAPH, FUNCTIONS)
    assert (waits.median_s, waits.worst_s, waits.served, waits.count) == (0.0, 0.0, 1, 1)


@pytest.mark.parametrize("order", ["oldest", "smith"])
def test_every_request_of_a_burst_is_served_under_each_order(order):
    requests = bench.poisson_requests(0, 40.0, 400.0, GRAPH, PRIORITIES, FUNCTIONS)
    waits = bench.waits(requests, order, GRAPH, FUNCTIONS)
    assert waits.served == waits.count == len(requests)
    assert 0.0 <= waits.median_s <= waits.worst_s


def test_the_table_has_every_load_and_order(capsys):
    assert bench.main(["--seeds", "1"]) == 0
    out = capsys.readouterr().out
    for load in bench.LOADS:
        for order in ("oldest", "smith"):
            assert f"| {load} | {order} |" in out
    assert "ETA 0 s" in out


def test_no_seeds_is_refused():
    with pytest.raises(SystemExit):
        bench.main(["--seeds", "0"])
