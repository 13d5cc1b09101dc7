"""TAMP executor (Fig. 4-14) on the in-process navigation model: numbers from the timing rule."""

import numpy as np
import pytest
from planner_factories import make_instruction

from task_planner.baselines import FirstComeFirstServe, PriorityFirst
from task_planner.executor import Executor, ExecutorConfig, nearest_node
from task_planner.executor_commands import Execute, Navigate, Say, StopMotion, Verify
from task_planner.executor_sim import NavigationModel, run_executor
from task_planner.exact import ExactReplanner
from task_planner.people_belief import PeopleAtPlaces
from task_planner.problem import Problem, schedule_reward
from task_planner.ripple_planner import RipplePlanner
from task_planner.robot_functions import load_robot_functions
from task_planner.simulate import run_planner
from task_planner.step_planner import StepRipplePlanner
from task_planner.task_buffer import DONE, FAILED, PENDING, BufferConfig, TaskBuffer
from tamp_resources import resource

FUNCTIONS = load_robot_functions(
    resource("config") / "robot_functions.yaml")
A, B, C, D = range(4)  # line_graph: A -1- B -2- C -3- D (metres), 0.5 m/s


def make_executor(graph, planner, tmp_path, people=None, name="buffer.sqlite", start_node=A):
    buffer = TaskBuffer(tmp_path / name, BufferConfig(node_count=graph.size))
    return Executor(buffer, graph, planner, people or PeopleAtPlaces(), FUNCTIONS,
                    ExecutorConfig(speed_mps=0.5), start_node=start_node)


def done_rewards(executor):
    return {r.instruction.id: r.reward_earned for r in executor.buffer.records()
            if r.state == DONE}


def test_fcfs_run_earns_the_hand_computed_reward(line_graph, tmp_path):
    first = make_instruction(1, D, gamma=3.0, beta=0.94, duration=10, function=1)
    second = make_instruction(2, B, gamma=5.0, beta=0.9, duration=5, function=2)
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path)
    trace = run_executor(executor, [(0.0, first), (0.0, second)],
                         NavigationModel(line_graph, 0.5))
    # A->D is 6 m = 12 s, chat 10 s: done at 22; D->B 5 m = 10 s, encourage 5 s: done at 37.
    assert done_rewards(executor) == pytest.approx({1: 3 * 0.94 ** 22, 2: 5 * 0.9 ** 37})
    assert [node for _, node in trace.goals] == [B, C, D, C, B]
    assert trace.executed == [(12.0, 1, "chat"), (32.0, 2, "encourage")]
    assert trace.said[0] == (12.0, "Hello everyone, shall we have a chat?")


@pytest.mark.parametrize("planner", [RipplePlanner, FirstComeFirstServe, PriorityFirst,
                                     ExactReplanner])
def test_same_reward_as_the_offline_simulation(planner, star_graph, tmp_path):
    instructions = [make_instruction(1, 1, gamma=3.0, beta=0.94, duration=20, function=3),
                    make_instruction(2, 2, gamma=5.0, beta=0.90, duration=30, function=4),
                    make_instruction(3, 3, gamma=2.0, beta=0.98, duration=15, function=5),
                    make_instruction(4, 2, gamma=4.0, beta=0.95, duration=15, function=5,
                                     previous_id=1)]
    problem = Problem(star_graph, tuple(instructions), 0.5, 0)
    expected = schedule_reward(problem, run_planner(problem, planner()))
    executor = make_executor(star_graph, planner(), tmp_path)
    run_executor(executor, [(0.0, i) for i in instructions], NavigationModel(star_graph, 0.5))
    assert sum(done_rewards(executor).values()) == pytest.approx(expected)
    finished = {r.instruction.id: r.completion_time for r in executor.buffer.records()}
    assert finished[4] > finished[1]  # the chain through previous_id


def test_new_instruction_turns_the_robot_back_mid_edge(line_graph, tmp_path):
    far = make_instruction(1, D, gamma=1.0, beta=0.9, duration=0, function=1)
    urgent = make_instruction(2, A, gamma=9.0, beta=0.5, duration=0, function=4, start_time=1.0)
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    trace = run_executor(executor, [(0.0, far), (1.0, urgent)], NavigationModel(line_graph, 0.5))
    # Leaves A at 0 for B (2 s); at 1 s turns back and is at A at 2 s: 9 * 0.5 ** (2 - 1).
    assert trace.goals[:2] == [(0.0, B), (1.0, A)]
    assert done_rewards(executor)[2] == pytest.approx(4.5)
    # then A->D: 12 s, done at 14
    assert done_rewards(executor)[1] == pytest.approx(0.9 ** 14)


def test_abort_is_retried_then_fails_with_the_reason_and_the_rest_is_served(line_graph, tmp_path):
    behind_door = make_instruction(1, D, gamma=9.0, beta=0.9, duration=0, function=1)
    reachable = make_instruction(2, B, gamma=1.0, beta=0.9, duration=0, function=1)
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    navigation = NavigationModel(line_graph, 0.5, blocked={frozenset((C, D))}, abort_after_s=2.0)
    trace = run_executor(executor, [(0.0, behind_door), (0.0, reachable)], navigation)
    failed = executor.buffer.get(1)
    assert failed.state == FAILED
    assert failed.reason == "navigation to D aborted 3 times: no path to the goal"
    # A->C 6 s, three 2 s attempts at C->D: failed at 12 s; C->B 4 s: done at 16 s.
    assert failed.completion_time == pytest.approx(12.0)
    assert [node for _, node in trace.goals].count(D) == 3
    assert done_rewards(executor) == pytest.approx({2: 0.9 ** 16})


def test_person_not_at_destination_is_searched_at_last_known_places(line_graph, tmp_path):
    people = PeopleAtPlaces(now={"Bob": C}, before={"Bob": [B]})
    visit = make_instruction(1, D, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path, people)
    trace = run_executor(executor, [(0.0, visit)], NavigationModel(line_graph, 0.5))
    # A->D 12 s, Bob not there; D->C 6 s: found at 18 s, check_status 4 s: done at 22.
    assert trace.executed == [(18.0, 1, "check_status")]
    assert done_rewards(executor) == pytest.approx({1: 2 * 0.9 ** 22})
    assert (18.0, "Bob, how are you feeling right now?") in trace.said


def test_person_nowhere_fails_after_searching_every_known_place(line_graph, tmp_path):
    people = PeopleAtPlaces(now={"Bob": C}, before={"Bob": [B, C]})
    people.seen("Bob", None)  # he has gone out of sight
    assert people.last_known_places("Bob") == [C, B]
    visit = make_instruction(1, D, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path, people, start_node=D)
    trace = run_executor(executor, [(0.0, visit)], NavigationModel(line_graph, 0.5))
    record = executor.buffer.get(1)
    assert record.state == FAILED and record.reason == "Bob not found (searched D, C, B)"
    # D->C 6 s, C->B 4 s: failed at 10 s
    assert record.completion_time == pytest.approx(10.0)
    assert [node for _, node in trace.goals] == [C, B]
    assert trace.executed == []


def test_unknown_function_code_fails_naming_it(line_graph, tmp_path):
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path)
    commands = executor.receive([make_instruction(1, A, function=42)], now=0.0)[1]
    record = executor.buffer.get(1)
    assert record.state == FAILED and "unknown robot function code 42" in record.reason
    assert commands == [Say("Sorry, I could not complete request 1.")]


def test_refused_instruction_is_named_and_nothing_moves(line_graph, tmp_path):
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path)
    results, commands = executor.receive([make_instruction(1, 9, function=1)], now=0.0)
    assert results[0][0] is None and "destination node 9 is not in the graph" in results[0][1]
    assert commands == []


def test_restart_mid_run_loses_nothing_and_repeats_nothing(star_graph, tmp_path):
    instructions = [make_instruction(k, 1 + k % 3, gamma=1.0 + k, beta=0.95, duration=10,
                                     function=1) for k in range(1, 7)]
    arrivals = [(0.0, i) for i in instructions]
    reference = make_executor(star_graph, PriorityFirst(), tmp_path, name="reference.sqlite")
    run_executor(reference, arrivals, NavigationModel(star_graph, 0.5))
    expected = {r.instruction.id: r.completion_time for r in reference.buffer.records()}

    first = make_executor(star_graph, PriorityFirst(), tmp_path)
    trace = run_executor(first, arrivals, NavigationModel(star_graph, 0.5), until_s=65.0)
    done_before = {r.instruction.id: r.completion_time for r in first.buffer.records()
                   if r.state == DONE}
    killed_at = trace.executed[-1]
    assert 0 < len(done_before) < 6 and first.buffer.active_id() == killed_at[1]
    # done: 6 at L1 (18 s), 5 at L3 (44 s); killed at 65 s during 4 at L2 (started at 60 s).
    # restart: a fresh buffer on the same journal; the robot is where it was executing
    second = make_executor(star_graph, PriorityFirst(), tmp_path, start_node=first.node)
    assert second.buffer.resumed == 1 and second.buffer.get(killed_at[1]).state == PENDING
    # The restarted run replays its clock from the kill: functions restart, none finished repeats.
    later = run_executor(second, [], NavigationModel(star_graph, 0.5), start_s=65.0)
    assert all(r.state == DONE for r in second.buffer.records())
    assert {i: t for i, t in done_before.items()} == \
        {i: second.buffer.get(i).completion_time for i in done_before}
    repeated = [i for _, i, _ in later.executed if i in done_before]
    assert repeated == []
    assert done_before == {6: 18.0, 5: 44.0} and killed_at == (60.0, 4, "chat")
    assert later.executed[0] == (65.0, 4, "chat")  # restarted where it stood, at once
    assert second.buffer.get(4).completion_time == pytest.approx(75.0)
    assert sorted(expected) == sorted(r.instruction.id for r in second.buffer.records())


def test_navigate_commands_name_their_instruction(line_graph, tmp_path):
    executor = make_executor(line_graph, RipplePlanner(), tmp_path)
    commands = executor.receive([make_instruction(5, C, function=1)], now=0.0)[1]
    assert commands == [Navigate(B, 5)]
    assert executor.buffer.get(5).state == PENDING


def test_successor_arriving_before_its_predecessor_waits_for_it(line_graph, tmp_path):
    report = make_instruction(2, A, gamma=5.0, beta=0.9, duration=1, function=7, previous_id=1)
    check = make_instruction(1, B, gamma=1.0, beta=0.9, duration=2, function=3)
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    trace = run_executor(executor, [(0.0, report), (0.5, check)], NavigationModel(line_graph, 0.5))
    # nothing to do until 1 arrives at 0.5 s; A->B 2 s, check 2 s (done 4.5), B->A 2 s, report 1 s
    assert [(t, i) for t, i, _ in trace.executed] == [(2.5, 1), (6.5, 2)]
    assert done_rewards(executor) == pytest.approx({1: 0.9 ** 4.5, 2: 5 * 0.9 ** 7.5})


def test_nearest_node_is_where_a_restarted_robot_stands():
    from task_planner.graph import graph_from_edges
    graph = graph_from_edges("PQR", [("P", "Q", 2.0), ("Q", "R", 2.0)],
                             poses=[(0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 2.0, 0.0)])
    assert [nearest_node(graph, x, y) for x, y in [(0.4, 0.1), (1.6, 0.3), (2.1, 1.2)]] == [0, 1, 2]


def test_person_never_located_is_not_served_unchecked(line_graph, tmp_path):
    """Issue 12: the target must be verified; nobody has seen Zoe, so there is nowhere to search."""
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=1, target="Zoe")
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path, PeopleAtPlaces())
    trace = run_executor(executor, [(0.0, visit)], NavigationModel(line_graph, 0.5))
    record = executor.buffer.get(1)
    assert record.state == FAILED and record.reason == "Zoe not found (searched B)"
    assert record.completion_time == pytest.approx(2.0)   # A->B 2 s
    assert trace.executed == []


def look_executor(line_graph, tmp_path, people):
    buffer = TaskBuffer(tmp_path / "look.sqlite", BufferConfig(node_count=line_graph.size))
    return Executor(buffer, line_graph, FirstComeFirstServe(), people, FUNCTIONS,
                    ExecutorConfig(speed_mps=0.5, verify_wait_s=3.0), start_node=B)


def test_person_seen_while_the_robot_looks_is_served(line_graph, tmp_path):
    people = PeopleAtPlaces(now={"Bob": C})
    executor = look_executor(line_graph, tmp_path, people)
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    _, commands = executor.receive([visit], 0.0)
    assert commands == [Verify(1, "Bob", 3.0)] and executor.mode == "verifying"
    assert executor.tick(1.0) == [] and executor.buffer.get(1).state == PENDING
    people.seen("Bob", B)                  # perception places Bob here at 1.5 s
    commands = executor.tick(1.5)
    assert commands[0] == Execute(1, "check_status", 4.0) and executor.mode == "executing"


def test_person_not_seen_while_looking_is_searched_after_the_wait(line_graph, tmp_path):
    executor = look_executor(line_graph, tmp_path, PeopleAtPlaces(now={"Bob": C}))
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    executor.receive([visit], 0.0)
    assert executor.tick(2.9) == []
    assert executor.tick(3.0) == [Navigate(C, 1)]   # on to his last known place
    assert executor.state.search[1] == [C] and executor.state.searched[1] == [B]


def dynamic_household_arrivals(graph, count=12, seed=3):
    """Seeded requests over 10 minutes with Table 5-5 priorities and 15-60 s functions."""
    from task_planner.reward import load_priorities
    rng = np.random.default_rng(seed)
    rows = list(load_priorities(
        resource("config") / "priorities.yaml").values())
    arrivals = []
    for k in range(1, count + 1):
        row = rows[rng.integers(len(rows))]
        launch = float(np.round(rng.uniform(0, 600), 1))
        arrivals.append((launch, make_instruction(
            k, int(rng.integers(graph.size)), gamma=row.gamma, beta=row.beta,
            duration=int(rng.choice([15, 20, 30, 60])), function=1, start_time=launch)))
    return arrivals


def test_dynamic_fcfs_matches_the_offline_simulation_and_planners_beat_it(tmp_path):
    from task_planner.graph import load_graph
    from task_planner.rollout_planner import RolloutPlanner
    graph = load_graph(resource("maps") / "household.graph.yaml")
    arrivals = dynamic_household_arrivals(graph)
    problem = Problem(graph, tuple(i for _, i in arrivals), 0.5, 0)
    earned = {}
    for name, planner in (("fcfs", FirstComeFirstServe), ("rollout", RolloutPlanner),
                          ("seed", RipplePlanner)):
        executor = make_executor(graph, planner(), tmp_path, name=f"{name}.sqlite")
        run_executor(executor, arrivals, NavigationModel(graph, 0.5))
        assert all(r.state == DONE for r in executor.buffer.records())
        earned[name] = executor.buffer.total_reward()
    # FCFS never changes its target, so the executor reproduces the offline timing rule exactly
    assert earned["fcfs"] == pytest.approx(schedule_reward(
        problem, run_planner(problem, FirstComeFirstServe())))
    assert earned["rollout"] > earned["fcfs"] and earned["seed"] > earned["fcfs"]


def test_successor_whose_predecessor_never_arrives_fails_and_is_said(line_graph, tmp_path):
    report = make_instruction(2, A, gamma=5.0, beta=0.9, duration=1, function=7, previous_id=1)
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    assert executor.receive([report], now=0.0)[1] == []   # waits for 1, nothing to do
    assert executor.tick(299.0) == [] and executor.buffer.get(2).state == PENDING
    assert executor.tick(300.0) == [Say("Sorry, I could not complete request 2.")]
    assert executor.buffer.get(2).reason == "predecessor 1 never arrived (300 s after " \
                                            "instruction 2)"
    assert executor.log[-1] == (300.0, "failed 2: predecessor 1 never arrived (300 s after "
                                       "instruction 2)")


def test_a_fault_while_serving_fails_that_instruction_stops_and_serves_the_rest(line_graph,
                                                                                tmp_path):
    poison = make_instruction(1, D, gamma=9.0, beta=0.9, duration=0, function=1)
    other = make_instruction(2, B, gamma=1.0, beta=0.9, duration=0, function=1)
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    _, commands = executor.receive([poison, other], 0.0)
    assert commands[0] == Navigate(B, 1)  # towards D for the higher priority
    assert executor.serving() == 1
    commands = executor.fault(1.0, "ValueError: reward is nan")
    assert commands == [StopMotion(), Say("Sorry, I could not complete request 1.")]
    failed = executor.buffer.get(1)
    assert failed.state == FAILED
    assert failed.reason == "fault while serving it: ValueError: reward is nan"
    assert executor.mode == "idle" and executor.serving() == 0
    assert executor.tick(1.0)[0] == Navigate(B, 2)  # the next tick serves the other one
    executor.buffer.close()
    reopened = TaskBuffer(tmp_path / "buffer.sqlite")  # a restart never re-runs it
    assert [r.instruction.id for r in reopened.open_records()] == [2]


def test_a_fault_while_idle_only_stops(line_graph, tmp_path):
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    assert executor.fault(0.0, "KeyError: 'x'") == [StopMotion()]
    assert executor.log[-1] == (0.0, "fault: KeyError: 'x'")


def test_a_step_planner_is_refused_with_a_reason(line_graph, tmp_path):
    with pytest.raises(ValueError, match="decides every step along an edge"):
        make_executor(line_graph, StepRipplePlanner(), tmp_path)


def test_a_function_over_early_finishes_at_the_next_tick(line_graph, tmp_path):
    """An introduce dialogue that is over ends its 60 s function: the robot does not stand
    there for the rest of the minute."""
    executor = make_executor(line_graph, FirstComeFirstServe(), tmp_path)
    commands = executor.receive([make_instruction(1, A, duration=60, function=9, type=1,
                                                  source="robot")], now=0.0)[1]
    assert Execute(1, "introduce", 60.0) in commands
    assert not executor.function_over(2, 8.0)            # not the one executing
    assert executor.function_over(1, 8.0)
    executor.tick(8.0)
    record = executor.buffer.get(1)
    assert (record.state, record.completion_time) == (DONE, 8.0)
    assert not executor.function_over(1, 9.0)            # over already
