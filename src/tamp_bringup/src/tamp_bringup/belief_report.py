"""How well the robot knew the people during a scenario run (ROS-free): belief accuracy against
the simulator's ground truth, the searches, the people it met, and its own instructions.

Ground truth is used here only to grade the run; the robot never saw it.
"""
import sqlite3
from pathlib import Path

from task_planner.instruction import ROBOT
from task_planner.task_buffer import journalled_searches


def place_at(changes, t):
    """The place of a [[t, place], ...] change list at time t [s]; "" before the first entry."""
    place = ""
    for when, where in changes:
        if when > t:
            break
        place = where
    return place


def belief_accuracy(truth, belief, start_s, end_s, step_s=0.5):
    """Share of [start_s, end_s] in which the believed place equals the true place, sampled
    every step_s [s]; an unknown belief ("") is wrong. Returns 0.0 for an empty interval."""
    samples = [start_s + k * step_s for k in range(int((end_s - start_s) / step_s) + 1)]
    if not samples or end_s <= start_s:
        return 0.0
    hits = sum(place_at(belief, t) == place_at(truth, t) != "" for t in samples)
    return hits / len(samples)


def people_accuracy(record):
    """{name: belief accuracy} over the run, for everyone the robot knew; a visitor met during
    the run counts from their registration, under the name the robot registered them by."""
    met = {r["visitor"]: r for r in record.get("registrations", [])}
    end_s = float(record["sim_s"])
    figures = {}
    for person, truth in sorted(record.get("truth", {}).items()):
        name = met[person]["name"] if person in met else person
        belief = record.get("belief", {}).get(name)
        if belief is None:
            continue
        start = met[person]["time"] if person in met else max(0.0, truth[0][0])
        figures[name] = belief_accuracy(truth, belief, start, end_s)
    return figures


def read_searches(journal_path):
    """The executor's journalled searches, read without changing the file."""
    uri = f"file:{Path(journal_path).resolve()}?mode=ro"
    with sqlite3.connect(uri, uri=True) as db:
        return journalled_searches(db)


def interruptions(searches, entries):
    """Per search (in order), the ids of the other instructions whose service began while it
    went on: the instructions that interrupted it."""
    return [[e.instruction.id for e in entries
             if e.instruction.id != i and start < e.started_s < end]
            for i, _, start, end, _, _ in searches]


def history_sources(humans_path):
    """{source: rows} of a human database's history, read without changing the file."""
    uri = f"file:{Path(humans_path).resolve()}?mode=ro"
    with sqlite3.connect(uri, uri=True) as db:
        return dict(db.execute("SELECT source, COUNT(*) FROM history GROUP BY source "
                               "ORDER BY source").fetchall())


def belief_markdown(record, entries, searches, t0, sources=None):
    """The report's section on what the robot knew of the people; `sources`: history_sources
    of the run's human database."""
    accuracy = people_accuracy(record)
    mean = sum(accuracy.values()) / len(accuracy) if accuracy else 0.0
    lines = ["## What the robot knew of the people", "",
             "Belief accuracy: the share of the run in which the place human_db held for a "
             "person (written only by the robot's perception and registration) was the place "
             "the simulator had them in (ground truth, used for this report only; sampled every "
             f"0.5 s, an unknown place counts as wrong). Mean **{mean:.2f}**.", "",
             "| person | belief accuracy |", "|---|---|"]
    lines += [f"| {name} | {value:.2f} |" for name, value in accuracy.items()]
    if sources:
        lines += ["", "human_db's history rows by who wrote them (perception and registration "
                  "only: nothing came from the scenario): "
                  + ", ".join(f"{source} {count}" for source, count in sources.items()) + "."]
    lines += ["", "Searches (a person not where the robot believed them):", ""]
    if searches:
        lines += ["| instruction | person | began [s] | took [s] | places looked at | outcome | "
                  "interrupted by |", "|---|---|---|---|---|---|---|"]
        lines += [f"| {i} | {target} | {start - t0:.1f} | {end - start:.1f} | "
                  f"{', '.join(places)} | {'found' if found else 'not found'} | "
                  f"{', '.join(map(str, cut))} |"
                  for (i, target, start, end, found, places), cut
                  in zip(searches, interruptions(searches, entries))]
    else:
        lines.append("none: every person was where the robot looked first.")
    lines += ["", "People met (registered through the introduction dialogue):", ""]
    met = record.get("registrations", [])
    lines += [f"- {r['name']} at {r['time']:.1f} s (dialogue {r.get('dialogue_s', 0.0):.1f} s)"
              for r in met] or ["- nobody"]
    if record.get("recalls"):
        lines += ["", "Residents met by name (asked who they are, the shirt seen registered in "
                  "human_db):", ""]
        lines += [f"- {r['person']} in the {r['place']} at {r['time']:.1f} s "
                  f"({r.get('why', 'new clothes')}, dialogue {r['dialogue_s']:.1f} s)"
                  for r in record["recalls"]]
    own = [e for e in entries if e.instruction.type == ROBOT]
    lines += ["", f"The robot's own instructions: {len(own)} "
              f"({sum(e.state == 'done' for e in own)} served).", ""]
    if own:
        lines += ["| id | instruction | place | state | reward |", "|---|---|---|---|---|"]
        lines += [f"| {e.instruction.id} | {e.instruction.text.replace('|', '/')} | "
                  f"{e.instruction.destination_name} | {e.state} | {e.reward:.3f} |"
                  for e in own]
    return lines + [""]
