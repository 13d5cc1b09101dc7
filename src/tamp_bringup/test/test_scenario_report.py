"""Scenario report: journal read-back, the run's reward curve, counts, order checks, and the model
figures on the same arrivals, against hand-computed numbers."""
import pytest
from bringup_factories import instruction

from tamp_bringup.scenario_report import (GOALS_MODEL, MODEL_PLANNERS, arrivals_problem,
                                          check_order, fleet_figures, fleet_markdown,
                                          model_figures, read_fleet_journals, read_journal,
                                          report_markdown, run_curve, summary, timeline_rows)
from task_planner.planner_registry import SCENARIO_MODEL, planner_names
from task_planner.task_buffer import BufferConfig, TaskBuffer


SETTINGS = {"step_s": 1.0, "rollout_candidates": 6, "rollout_horizon": 10,
            "rollout_tail_weight": 0.5, "exact_max_instructions": 40}


def journal(tmp_path, graph, first_served):
    """Three instructions on A -1- B -2- C -3- D launched at t = 0: 1 (gamma 2, beta 0.5) and
    2 (gamma 4, beta 0.5) on B lasting 1 s; 3 (gamma 1, beta 0.9) on C after 2, lasting 0 s."""
    path = tmp_path / "tasks.sqlite"
    buffer = TaskBuffer(path, BufferConfig(node_count=graph.size))
    buffer.submit_many([instruction(1, 1, 2.0, 0.5, 1, source="Bob", text="hi"),
                        instruction(2, 1, 4.0, 0.5, 1, source="Ann"),
                        instruction(3, 2, 1.0, 0.9, 0, previous_id=2, source="Ann")], 0.0)
    second = 1 if first_served == 2 else 2
    buffer.start(first_served, 1.0)
    buffer.finish(first_served, 2.0)
    buffer.start(second, 2.0)
    buffer.finish(second, 3.0)
    buffer.start(3, 5.0)
    buffer.finish(3, 5.0)
    buffer.close()
    return path


def test_a_fleets_journals_count_each_instruction_once_from_the_robot_that_served_it(
        tmp_path, line_graph):
    paths = []
    for robot, mine, theirs in (("a", 1, 2), ("b", 2, 1)):
        paths.append(tmp_path / f"{robot}.sqlite")
        buffer = TaskBuffer(paths[-1], BufferConfig(node_count=line_graph.size))
        buffer.submit_many([instruction(1, 1, 2.0, 0.5, 1), instruction(2, 1, 4.0, 0.5, 1)], 0.0)
        buffer.start(mine, 1.0)
        buffer.finish(mine, 2.0)
        buffer.close_elsewhere(theirs, 3.0, 2, f"done by {'b' if robot == 'a' else 'a'}")
        buffer.close()
    entries = read_fleet_journals(paths)
    assert [(e.instruction.id, e.state, e.completion_s, e.reason) for e in entries] == [
        (1, "done", 2.0, ""), (2, "done", 2.0, "")]
    assert summary(entries)["reward"] == pytest.approx(2 * 0.5 ** 2 + 4 * 0.5 ** 2)
    assert read_fleet_journals(paths[:1]) == read_journal(paths[0])


def test_a_fleets_journals_prefer_a_closed_entry_to_an_open_one(tmp_path, line_graph):
    """A robot that stopped before it learnt that the other served an instruction holds it
    open; the report counts it as the other's."""
    paths = [tmp_path / "a.sqlite", tmp_path / "b.sqlite"]
    for path in paths:
        buffer = TaskBuffer(path, BufferConfig(node_count=line_graph.size))
        buffer.submit_many([instruction(1, 1, 2.0, 0.5, 1)], 0.0)
        if path.stem == "b":
            buffer.start(1, 1.0)
            buffer.finish(1, 2.0)
        buffer.close()
    for order in (paths, paths[::-1]):
        [entry] = read_fleet_journals(order)
        assert (entry.state, entry.completion_s) == ("done", 2.0)


def test_journal_curve_counts_and_order(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=2))
    assert [(e.instruction.id, e.state, e.started_s, e.completion_s) for e in entries] == [
        (1, "done", 2.0, 3.0), (2, "done", 1.0, 2.0), (3, "done", 5.0, 5.0)]
    # 4 * 0.5^2 = 1.0 at 2 s, 2 * 0.5^3 = 0.25 at 3 s, 0.9^5 = 0.59049 at 5 s
    times, rewards = run_curve(entries, t0=0.0)
    assert times == (2.0, 3.0, 5.0)
    assert rewards == pytest.approx((1.0, 1.25, 1.84049))
    stats = summary(entries)
    assert (stats["requests"], stats["served"], stats["failed"]) == (3, 3, 0)
    assert stats["reward"] == pytest.approx(1.84049)
    assert check_order(entries) == []
    rows = timeline_rows(entries, t0=0.0)
    assert [(r["id"], r["launch"], r["start"], r["end"]) for r in rows] == [
        (1, 0.0, 2.0, 3.0), (2, 0.0, 1.0, 2.0), (3, 0.0, 5.0, 5.0)]


def test_lower_priority_first_at_the_same_place_is_reported(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=1))
    assert check_order(entries) == [
        "1 (gamma 2.0) started at 1.0 s while 2 (gamma 4.0) waited at the same place"]


def test_people_served_where_found_are_not_compared_by_place(tmp_path, line_graph):
    path = tmp_path / "people.sqlite"
    buffer = TaskBuffer(path, BufferConfig(node_count=line_graph.size))
    buffer.submit_many([instruction(1, 1, 2.0, 0.5, 1, source="Bob", target="Bob"),
                        instruction(2, 1, 4.0, 0.5, 1, source="Ann", target="Ann")], 0.0)
    buffer.start(1, 1.0)     # Bob found first; Ann, believed at the same place, was elsewhere
    buffer.finish(1, 2.0)
    buffer.close()
    assert check_order(read_journal(path)) == []


def test_model_figures_on_the_same_arrivals(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=2))
    problem = arrivals_problem(line_graph, entries, speed_mps=1.0, start_node=0, t0=0.0)
    figures = {f.name: f for f in model_figures(problem, SETTINGS)}
    # FCFS from A: B at 1 s, 1 done at 2 (2 * 0.5^2), 2 done at 3 (4 * 0.5^3), C at 5 (0.9^5)
    fcfs = figures["FCFS (model)"]
    assert fcfs.order == (1, 2, 3)
    assert fcfs.reward == pytest.approx(0.5 + 0.5 + 0.59049)
    # the optimum serves 2 first: 1.0 + 0.25 + 0.59049
    exact = figures["Exact optimum (model, arrivals known)"]
    assert exact.order == (2, 1, 3)
    assert exact.reward == pytest.approx(1.84049)
    assert exact.curve[0] == (2.0, 3.0, 5.0)


def test_one_robot_or_two_on_the_same_arrivals(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=2))
    problem = arrivals_problem(line_graph, entries, speed_mps=1.0, start_node=0, t0=0.0)
    fleet = fleet_figures(problem, SETTINGS)
    # two robots from A: 1 and 2 both done at 2 s (0.5 + 1.0), 3 on C after 2 at 4 s (0.9^4)
    assert fleet["exact"] == {1: pytest.approx(1.84049), 2: pytest.approx(2.1561)}
    for name in ("seed", "rollout", "auction"):
        assert all(fleet[name][k] <= fleet["exact"][k] + 1e-9 for k in (1, 2))
    assert fleet["auction"][2] == pytest.approx(2.1561)
    known = fleet_figures(problem, SETTINGS, single_exact=1.5)    # one robot's taken as given
    assert known["exact"] == {1: 1.5, 2: pytest.approx(2.1561)}
    lines = fleet_markdown(fleet)
    assert lines[0] == "## One robot or two (model)"
    assert "| exact | 1.840 | 2.156 |" in lines


def test_arrivals_are_shifted_to_the_scenario_start(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=2))
    problem = arrivals_problem(line_graph, entries, 1.0, 0, t0=-4.0)
    assert problem.launch.tolist() == [4.0, 4.0, 4.0]


def test_the_model_serves_a_person_where_the_simulator_had_them_at_the_launch(tmp_path,
                                                                             line_graph):
    path = tmp_path / "tasks.sqlite"
    buffer = TaskBuffer(path, BufferConfig(node_count=line_graph.size))
    buffer.submit_many([instruction(1, 1, 2.0, 0.5, 1, target="Bob", start_time=10.0),
                        instruction(2, 1, 2.0, 0.5, 1, target="Cy", start_time=10.0),
                        instruction(3, 1, 2.0, 0.5, 1, target="Al", start_time=10.0),
                        instruction(4, 1, 2.0, 0.5, 1, start_time=10.0)], 10.0)
    buffer.close()
    truth = {"Bob": [[0.0, "C"], [9.0, "D"], [11.0, "A"]],   # on D at the launch
             "Cy": [[0.0, "hall"]]}                          # in no place of the graph
    problem = arrivals_problem(line_graph, read_journal(path), 1.0, 0, 0.0, truth)
    assert problem.node.tolist() == [3, 1, 1, 1]
    assert arrivals_problem(line_graph, read_journal(path), 1.0, 0, 0.0).node.tolist() == \
        [1, 1, 1, 1]


def test_markdown_lists_every_instruction(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=2))
    problem = arrivals_problem(line_graph, entries, 1.0, 0, 0.0)
    figures = model_figures(problem, SETTINGS)
    record = dict(scenario="t", command="scripts/run_scenario t", date="d", speed=5.0,
                  planner="rollout", start_place="A", t0=0.0, sim_s=6.0, wall_s=2.0,
                  finished=True, events=[dict(time=0.0, what="Bob sends: \"hi\"")],
                  requests=[dict(time=0.0, person="Bob", text="hi", spoken=True)],
                  trajectory=[[0.0, 0.0, 0.0]])
    text = report_markdown(record, entries, figures, run_curve(entries, 0.0), [],
                           dict(rewards="r.png", trajectory="t.png"))
    assert "phone requests sent: 1 (1 spoken through the STT node)" in text
    assert "served 3, failed 0" in text
    assert "| 1 | Bob | hi | " in text
    model = {f.name: f for f in figures}[dict(MODEL_PLANNERS)[GOALS_MODEL]]
    row = next(line for line in text.splitlines() if line.startswith("| 1 | Bob | hi | "))
    cells = [c.strip() for c in row.split("|")[1:-1]]
    assert cells[9] == f"{model.starts[1]:.1f}"    # the start the goals' model gives it
    assert "| this run (simulator) | 1.840 | 2, 1, 3 |" in text
    assert "| FCFS (model) | 1.590 | 1, 2, 3 |" in text
    assert "Replay in rviz" not in text
    replayed = report_markdown(record, entries, figures, run_curve(entries, 0.0), [],
                               dict(rewards="r.png", trajectory="t.png"),
                               replay="roslaunch tamp_bringup replay.launch bag:=/r/run.bag")
    assert "## Replay in rviz" in replayed
    assert "\nroslaunch tamp_bringup replay.launch bag:=/r/run.bag\n" in replayed


def test_model_figures_take_their_planners_from_the_registry():
    assert [name for name, _ in MODEL_PLANNERS] == list(planner_names(SCENARIO_MODEL))
