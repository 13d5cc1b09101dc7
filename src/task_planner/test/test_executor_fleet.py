"""Executors of a fleet on one pool (fleet_link): shared instructions, claims, chains across
robots, a killed robot's instruction served by the other, nothing twice, nothing lost."""
import pytest
from planner_factories import make_instruction

from task_planner.executor import Executor, ExecutorConfig
from task_planner.executor_sim import NavigationModel, run_executor_fleet
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import CANCELLED, DONE, FleetPool
from task_planner.people_belief import PeopleAtPlaces
from task_planner.ripple_planner import RipplePlanner
from task_planner.robot_functions import load_robot_functions
from task_planner import task_buffer
from task_planner.task_buffer import BufferConfig, TaskBuffer
from tamp_resources import resource

FUNCTIONS = load_robot_functions(resource("config") / "robot_functions.yaml")
A, B, C, D = range(4)  # line_graph: A -1- B -2- C -3- D (metres), 0.5 m/s


def fleet(graph, tmp_path, starts, lease_s=10.0, **config):
    """One executor per start node, robots "a", "b", ..., each with its journal, on one pool."""
    return [robot(graph, tmp_path, "ab"[k], start, lease_s, **config)
            for k, start in enumerate(starts)]


def robot(graph, tmp_path, name, start, lease_s=10.0, charging=None, **config):
    """(Re)start robot `name` at `start` on its journal `<name>.sqlite` and the fleet's pool."""
    buffer = TaskBuffer(tmp_path / f"{name}.sqlite", BufferConfig(node_count=graph.size))
    link = FleetLink(FleetPool(tmp_path / "pool.sqlite", lease_s=lease_s), name)
    return Executor(buffer, graph, RipplePlanner(), PeopleAtPlaces(), FUNCTIONS,
                    ExecutorConfig(speed_mps=0.5, **config), start_node=start,
                    charging=charging, fleet=link)


def served(executors):
    """{instruction id: [(robot, reward)]} of the DONE records that earned a reward."""
    found = {}
    for executor in executors:
        for record in executor.buffer.records():
            if record.state == task_buffer.DONE and not record.reason:
                found.setdefault(record.instruction.id, []).append(
                    (executor.fleet.robot, record.reward_earned))
    return found


def test_each_robot_serves_what_is_near_it_and_every_journal_knows_every_instruction(
        line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    near_a = make_instruction(1, A, gamma=5.0, beta=0.9, duration=4, function=1)
    near_b = make_instruction(2, D, gamma=3.0, beta=0.9, duration=4, function=2)
    run_executor_fleet([a, b], [(0.0, 0, near_a), (0.0, 0, near_b)],
                       NavigationModel(line_graph, 0.5))
    # a serves 1 where it stands; b takes 2 in at its first tick (t = 0) and serves it there:
    # both done at 4 s, and neither robot drives
    assert served([a, b]) == {1: [("a", pytest.approx(5 * 0.9 ** 4))],
                              2: [("b", pytest.approx(3 * 0.9 ** 4))]}
    assert a.buffer.get(2).reason == "done by b" and a.buffer.get(2).reward_earned == 0
    assert b.buffer.get(1).reason == "done by a"
    assert (a.node, b.node) == (A, D)
    entries = {e.id: (e.state, e.robot, e.claims) for e in a.fleet.pool.entries()}
    assert entries == {1: (DONE, "a", 1), 2: (DONE, "b", 1)}


def test_a_chain_crosses_robots_in_order(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(D, A))
    head = make_instruction(1, A, gamma=5.0, beta=0.9, duration=4, function=1)
    then = make_instruction(2, D, gamma=3.0, beta=0.9, duration=4, function=2, previous_id=1)
    busy = make_instruction(3, A, gamma=9.0, beta=0.9, duration=20, function=3, start_time=4.0)
    traces = run_executor_fleet([a, b], [(0.0, 1, head), (0.0, 1, then), (4.0, 1, busy)],
                                NavigationModel(line_graph, 0.5))
    # b, at A, serves the head where it stands (0 -> 4 s), then 3, which reaches it as the head
    # ends and is also at A (4 -> 24 s); a, at D, has taken the chain in at its tick at 0.25 s
    # and waits for the head; it learns that the head is done at its next tick after b's,
    # 4.25 s, and serves 2 where it stands
    assert served([a, b]) == {1: [("b", pytest.approx(5 * 0.9 ** 4))],
                              2: [("a", pytest.approx(3 * 0.9 ** 8.25))],
                              3: [("b", pytest.approx(9 * 0.9 ** 20))]}
    assert traces[0].executed == [(4.25, 2, "encourage")]
    assert a.buffer.get(1).reason == "done by b"


def test_a_killed_robots_instruction_is_served_by_the_other_once(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D), lease_s=10.0)
    long_one = make_instruction(1, B, gamma=9.0, beta=0.99, duration=30, function=1)
    others = [make_instruction(i, node, gamma=2.0, beta=0.99, duration=2, function=2)
              for i, node in ((2, D), (3, C), (4, A))]
    late = make_instruction(5, C, gamma=2.0, beta=0.99, duration=2, function=2, start_time=8.0)
    arrivals = [(0.0, 0, long_one)] + [(3.0, 0, i) for i in others] + [(8.0, 1, late)]
    traces = run_executor_fleet([a, b], arrivals, NavigationModel(line_graph, 0.5),
                                kills=[(6.0, 0)])
    # a drives A -> B (2 s) and executes 1 from 2 s; 2-4 reach it at 3 s and b serves them; a
    # is killed at 6 s holding 1 (ACTIVE in its journal), its lease renewed last at 5.25 s, so
    # 1 is claimable again after 15.25 s; 5 reaches b after the kill
    assert traces[0].executed == [(2.0, 1, "chat")]
    assert a.buffer.get(1).state == task_buffer.ACTIVE
    got = served([a, b])
    assert sorted(got) == [1, 2, 3, 4, 5]                  # none lost
    assert all(len(robots) == 1 for robots in got.values())  # none twice
    assert got[1][0][0] == "b"
    start_1 = next(t for t, i, _ in traces[1].executed if i == 1)
    assert start_1 >= 15.25
    entries = {e.id: e for e in b.fleet.pool.entries()}
    assert (entries[1].state, entries[1].robot, entries[1].claims) == (DONE, "b", 2)
    assert all(e.state == DONE for e in entries.values())


def test_ids_are_the_fleets_and_a_clashing_id_is_refused_naming_it(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    first = make_instruction(a.new_id(), B, function=1)
    assert first.id == 1
    a.receive([first], 0.0)
    assert b.new_id() == 2                                 # b's journal is still empty
    clash = make_instruction(1, C, function=2)
    results, _ = b.receive([clash], 0.0)
    assert results == [(None, "instruction 1: the fleet pool holds another instruction under "
                              "this id (let the fleet choose: id 0)")]
    assert not b.buffer.holds(1)


def test_a_cancel_through_one_robot_closes_it_for_the_other(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    far = make_instruction(1, C, gamma=2.0, beta=0.99, duration=5, function=1)
    a.receive([far], 0.0)
    b.tick(0.0)                                            # b takes it in
    a.cancel(1, 0.5)
    assert [e.state for e in a.fleet.pool.entries()] == [CANCELLED]
    b.tick(1.0)
    record = b.buffer.get(1)
    assert (record.state, record.reason) == (task_buffer.CANCELLED, "cancelled by a")


def test_a_robots_own_instruction_is_never_shared_and_a_lost_lease_is_told(tmp_path):
    pool = FleetPool(tmp_path / "pool.sqlite", lease_s=10.0)
    mine, other = FleetLink(pool, "a"), FleetLink(pool, "b")
    mine.keep_local(7)                                     # e.g. its charging instruction
    assert mine.share([make_instruction(7, A), make_instruction(8, B)]) == {}
    assert [i.id for i in other.news()] == [8]
    assert mine.claim(7, 0.0) and mine.holds(7, 100.0) and mine.close(7, 1.0, DONE) == ""
    assert mine.claim(8, 0.0) and mine.held == 8
    mine.renew(20.0)                                       # the lease ran out at 10 s
    assert mine.held == 0
    assert other.claim(8, 21.0)
    assert mine.close(8, 22.0, DONE) == ("robot 'a' does not hold instruction 8 at 22.000 s: "
                                         "held by 'b' until 31.000 s")


H, L1, L2 = range(3)  # star_graph: hub H, leaves L1, L2, L3 at 4 m (8 s at 0.5 m/s)


@pytest.mark.parametrize("wait_s, b_leaves_at", [(60.0, 16.25), (5.0, 5.0)])
def test_one_robot_at_a_time_drives_through_a_corridor(star_graph, tmp_path, wait_s,
                                                       b_leaves_at):
    a, b = fleet(star_graph, tmp_path, starts=(L1, L2), corridors=(H,), corridor_wait_s=wait_s)
    to_l2 = make_instruction(1, L2, gamma=2.0, beta=0.99, function=1)
    to_l1 = make_instruction(2, L1, gamma=2.0, beta=0.99, function=2)
    traces = run_executor_fleet([a, b], [(0.0, 0, to_l2), (0.0, 1, to_l1)],
                                NavigationModel(star_graph, 0.5))
    # a enters the hub at 0 s and leaves it on reaching L2 at 16 s; b, waiting since 0 s and
    # looking again every second, drives at its first look after that (16.25 s: its tick), or
    # after its 5 s limit; its move to the hub is its first goal
    assert traces[0].goals == [(0.0, H), (8.0, L2)]
    assert traces[1].goals[0] == (pytest.approx(b_leaves_at, abs=1.0), H)
    assert served([a, b]) == {1: [("a", pytest.approx(2 * 0.99 ** 16))],
                              2: [("b", pytest.approx(2 * 0.99 ** (traces[1].goals[0][0] + 16)))]}
    assert any(text == "wait: a is in H" for _, text in b.log)
    assert a.fleet.corridors == set() and b.fleet.corridors == set()


@pytest.mark.parametrize("one_per_place, b_serves", [(True, []), (False, [2])])
def test_one_robot_per_place_leaves_a_places_instructions_to_the_robot_there(
        line_graph, tmp_path, one_per_place, b_serves):
    a, b = fleet(line_graph, tmp_path, starts=(A, D), one_robot_per_place=one_per_place)
    first = make_instruction(1, C, gamma=5.0, beta=0.99, duration=10, function=1)
    second = make_instruction(2, C, gamma=4.0, beta=0.99, duration=10, function=2)
    traces = run_executor_fleet([a, b], [(0.0, 0, first), (0.0, 0, second)],
                                NavigationModel(line_graph, 0.5))
    # a takes 1 (it decides first) and drives A -> C (6 s); b, at D, would take 2 at C too,
    # unless a holds a claim at C; then a serves 2 after 1 (16 -> 26 s)
    assert [i for _, i, _ in traces[1].executed] == b_serves
    assert sorted(served([a, b])) == [1, 2]
