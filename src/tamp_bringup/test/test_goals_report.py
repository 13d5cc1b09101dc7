"""tamp_bringup.goals_report: each figure of a run beside its goal, on hand-computed numbers."""
import dataclasses

from test_scenario_report import SETTINGS, journal

from tamp_bringup.goals_report import (goals_markdown, needless_meetings, run_goals,
                                       service_delays)
from tamp_bringup.scenario_report import (JournalEntry, arrivals_problem, model_figures,
                                          read_journal)
from task_planner.instruction import ROBOT


def figures_and_entries(tmp_path, line_graph):
    entries = read_journal(journal(tmp_path, line_graph, first_served=2))
    problem = arrivals_problem(line_graph, entries, speed_mps=1.0, start_node=0, t0=0.0)
    return {f.name: f for f in model_figures(problem, SETTINGS)}, entries


def test_service_delays_against_the_model_schedule(tmp_path, line_graph):
    figures, entries = figures_and_entries(tmp_path, line_graph)
    fcfs = figures["FCFS (model)"]
    # FCFS from A at 1 m/s: 1 starts at B at 1 s, 2 at 2 s (after 1's 1 s), 3 at C at 5 s;
    # the run started 2 at 1 s, 1 at 2 s and 3 at 5 s
    assert fcfs.starts == {1: 1.0, 2: 2.0, 3: 5.0}
    assert service_delays(entries, fcfs.starts, 0.0) == {1: 1.0, 2: -1.0, 3: 0.0}
    assert service_delays(entries, fcfs.starts, -2.0) == {1: 3.0, 2: 1.0, 3: 2.0}


def test_each_figure_beside_its_goal(tmp_path, line_graph):
    figures, entries = figures_and_entries(tmp_path, line_graph)
    record = dict(sim_s=6.0, registrations=[],
                  truth={"Bob": [[0.0, "A"]], "Ann": [[0.0, "B"]]},
                  belief={"Bob": [[0.0, "A"]], "Ann": [[3.0, "B"]]})
    searches = [(1, "Bob", 10.0, 80.0, True, ["A", "B"]),
                (2, "Ann", 0.5, 100.0, True, ["B"])]   # 1 and 3 began during it (2 s, 5 s)
    goals = {g.figure: g for g in run_goals(record, entries, searches,
                                            figures["FCFS (model)"], 0.0)}
    assert goals["person requests served"].value == "3 of 3"
    median = goals["service start after the model's (FCFS (model)), median"]
    worst = goals["service start after the model's (FCFS (model)), worst"]
    assert (median.value, median.met, worst.value, worst.met) == ("0 s", True, "1 s", True)
    longest = goals["longest search not interrupted by another instruction"]
    assert (longest.value, longest.met) == ("70 s (1 of 2 interrupted)", False)
    assert goals["the robot's own instructions served"].value == "0 of 0"
    belief = goals["belief accuracy from the run start, lowest resident"]
    # Ann is believed at B from 3 s on: 7 of the 13 samples 0, 0.5, ..., 6 s
    assert belief.value == f"{7 / 13:.2f} (Ann)" and not belief.met
    share = goals["run reward / the model's (FCFS (model))"]
    assert share.value == f"1.840 / 1.590 = {1.84049 / 1.59049:.2f}" and share.met
    lines = goals_markdown(list(goals.values()))
    assert lines[0] == "## Goals"
    assert "| longest search not interrupted by another instruction | 70 s (1 of 2 interrupted) " \
        "| ≤ 60 s | **no** |" in lines


def test_a_meeting_cancelled_as_its_stranger_says_who_they_are_is_not_counted(tmp_path,
                                                                                line_graph):
    """The introduction node cancels the meeting of a stranger who said yes to "are you
    Carol?" while registering Carol's shirt: not an unserved instruction of the robot's."""
    figures, entries = figures_and_entries(tmp_path, line_graph)
    meeting = dataclasses.replace(entries[0].instruction, id=7, type=ROBOT, source="robot",
                                  destination_name="B",
                                  text="meet the unknown person in B (shirt (1, 2, 3))")
    cancelled = JournalEntry(meeting, "cancelled", 1.0, 0.0, 4.0, 0.0, "cancelled by request")
    unserved = dataclasses.replace(cancelled, instruction=dataclasses.replace(meeting, id=8),
                                   completion_s=40.0)
    recall = dict(time=4.5, person="Carol", place="B", dialogue_s=3.0, why="new clothes")
    record = dict(sim_s=60.0, registrations=[], recalls=[recall])
    assert needless_meetings([cancelled, unserved], [recall], 0.0) == [cancelled]
    assert needless_meetings([cancelled], [dict(recall, place="A")], 0.0) == []
    # the record's times count from the run start t0, the journal's do not
    later = dataclasses.replace(cancelled, completion_s=40.0)
    assert needless_meetings([later], [dict(recall, time=10.5)], 30.0) == [later]
    assert needless_meetings([later], [dict(recall, time=40.5)], 30.0) == []
    goals = {g.figure: g for g in run_goals(record, entries + [cancelled], [],
                                            figures["FCFS (model)"], 0.0)}
    own = goals["the robot's own instructions served"]
    assert (own.value, own.met) == ("0 of 0 (1 meeting(s) needless: the stranger said who "
                                    "they are)", True)
    goals = {g.figure: g for g in run_goals(record, entries + [cancelled, unserved], [],
                                            figures["FCFS (model)"], 0.0)}
    own = goals["the robot's own instructions served"]
    assert (own.value, own.met) == ("0 of 1 (1 meeting(s) needless: the stranger said who "
                                    "they are)", False)
