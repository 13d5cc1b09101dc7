"""Belief accuracy against ground truth and the report section, on hand-computed runs."""
import pytest
from bringup_factories import instruction

from tamp_bringup.belief_report import (belief_accuracy, belief_markdown, history_sources,
                                        people_accuracy, place_at, read_searches)
from task_planner.executor_commands import Search
from task_planner.instruction import ROBOT
from tamp_bringup.scenario_report import read_journal
from task_planner.task_buffer import BufferConfig, TaskBuffer



def test_place_at_follows_the_changes():
    changes = [[0.0, "sofa"], [10.0, "kitchen"]]
    assert [place_at(changes, t) for t in (-1.0, 0.0, 9.9, 10.0, 50.0)] == \
        ["", "sofa", "sofa", "kitchen", "kitchen"]


def test_accuracy_counts_unknown_and_stale_beliefs_as_wrong():
    truth = [[0.0, "living_room"], [40.0, "dining_room"]]
    belief = [[0.0, ""], [10.0, "living_room"], [60.0, "dining_room"]]
    # samples every 0.5 s over [0, 100]: 201; right on [10, 40) = 60 and [60, 100] = 81
    assert belief_accuracy(truth, belief, 0.0, 100.0) == pytest.approx(141 / 201)
    assert belief_accuracy(truth, belief, 5.0, 5.0) == 0.0


def test_a_person_met_during_the_run_counts_from_the_registration():
    record = dict(sim_s=100.0, registrations=[dict(visitor="Frank", name="Frans", time=50.0)],
                  truth={"Frank": [[0.0, "welcome"]], "Bob": [[0.0, "living_room"]]},
                  belief={"Frans": [[50.0, "welcome"]], "Bob": [[0.0, ""]]})
    # Frank, registered under the name the robot heard, counts from his registration
    assert people_accuracy(record) == {"Bob": 0.0, "Frans": 1.0}


def test_section_lists_searches_meetings_and_own_instructions(tmp_path, line_graph):
    path = tmp_path / "tasks.sqlite"
    buffer = TaskBuffer(path, BufferConfig(node_count=line_graph.size))
    buffer.submit_many([instruction(1, 1, 2.0, 0.5, 1, source="Bob", target="Bob"),
                        instruction(100000, 2, 1.0, 0.9, 5, type=ROBOT, source="robot",
                                         target="Bob", text="remind Bob: time to eat")], 0.0)
    buffer.store_search(Search(1, "Bob", 12.0, 30.5, True, ("B", "C")))
    buffer.start(100000, 2.0)
    buffer.finish(100000, 7.0)
    buffer.close()
    record = dict(sim_s=40.0, truth={"Bob": [[0.0, "B"]]}, belief={"Bob": [[20.0, "B"]]},
                  registrations=[dict(visitor="Frank", name="Frank", time=20.0,
                                      dialogue_s=14.5)],
                  recalls=[dict(person="Bob", place="B", time=30.0, dialogue_s=6.0,
                                why="first meeting")])
    text = "\n".join(belief_markdown(record, read_journal(path), read_searches(path), t0=2.0))
    assert "| Bob | 0.51 |" in text          # 41 of the 81 samples of [0, 40] from 20 s on
    assert "| 1 | Bob | 10.0 | 18.5 | B, C | found |  |" in text   # 100000 began before it
    assert "- Frank at 20.0 s (dialogue 14.5 s)" in text
    assert "- Bob in the B at 30.0 s (first meeting, dialogue 6.0 s)" in text
    assert "own instructions: 1 (1 served)" in text
    assert f"| 100000 | remind Bob: time to eat |  | done | {0.9 ** 7:.3f} |" in text


def test_history_rows_are_counted_by_source(tmp_path):
    import sqlite3
    path = tmp_path / "humans.sqlite"
    with sqlite3.connect(path) as db:
        db.execute("CREATE TABLE history (human_id, time, location, activity, source)")
        db.executemany("INSERT INTO history VALUES (1, 0, 'a', 'b', ?)",
                       [("perception",), ("register",), ("perception",)])
    sources = history_sources(path)
    assert sources == {"perception": 2, "register": 1}
    record = dict(sim_s=1.0, truth={}, belief={})
    text = "\n".join(belief_markdown(record, [], [], 0.0, sources))
    assert "nothing came from the scenario): perception 2, register 1." in text
