"""How a scenario run measures against the goals of a prompt, considerate companion (ROS-free):
each figure beside its goal, from the executor's journal, its searches, the scenario record and
the improved planner's model schedule on the same arrivals.

Goals: every person's request served; the start of each person's service at most 30 s (median)
and 120 s (worst) after the start the model gives it; every search that no other instruction
interrupted over within 60 s; every instruction the robot gave itself served before the run
ends (a meeting cancelled as its stranger said who they are is needless, not unserved); belief
accuracy from the run start at least 0.9 for every resident; the run's reward at least 0.6 of
the model's; activity recognition in the loop at least 0.7 in every category seen.
"""
from dataclasses import dataclass

import numpy as np

from tamp_bringup.activity_report import weakest
from tamp_bringup.belief_report import interruptions, people_accuracy
from task_planner.instruction import HUMAN, ROBOT

MEDIAN_DELAY_S, WORST_DELAY_S = 30.0, 120.0   # service start after the model's [s]
SEARCH_S = 60.0                                # longest search [s]
BELIEF = 0.9                                   # belief accuracy of each resident
REWARD_SHARE = 0.6                             # run reward / model reward
ACTIVITY = 0.7                                 # activity read right, per category
MEETING_TEXT = "meet the unknown person"       # perception.introduction's meeting instructions
RECALL_MATCH_S = 5.0                           # [s] a meeting cancelled this near a recall


@dataclass(frozen=True)
class Goal:
    """One figure of the run beside its goal."""

    figure: str
    value: str
    goal: str
    met: bool


def service_delays(entries, model_starts, t0):
    """{instruction id: the run's service start minus the model's [s]} for each person's
    instruction that both started; `model_starts`: ModelFigures.starts [s from t0]."""
    return {e.instruction.id: e.started_s - t0 - model_starts[e.instruction.id]
            for e in entries if e.instruction.type == HUMAN and e.started_s > 0
            and e.instruction.id in model_starts}


def needless_meetings(own, recalls, t0, within_s=RECALL_MATCH_S):
    """The meetings of `own` (the robot's journal entries) cancelled because the stranger said
    yes to "are you NAME?": the introduction node cancels the meeting as it registers NAME's
    shirt (a recall of the record, stamped from the run start `t0`, at the meeting's place
    within `within_s` of the cancel)."""
    return [e for e in own
            if e.state == "cancelled" and e.instruction.text.startswith(MEETING_TEXT)
            and any(r["place"] == e.instruction.destination_name
                    and abs(r["time"] - (e.completion_s - t0)) <= within_s for r in recalls)]


def run_goals(record, entries, searches, model, t0, categories=()):
    """The Goals of a run; `model`: the improved planner's ModelFigures on its arrivals,
    `searches`: the journalled searches ((id, target, start, end, found, places) tuples),
    `categories`: the activity categories (the affordance table's)."""
    human = [e for e in entries if e.instruction.type == HUMAN]
    served = sum(e.state == "done" for e in human)
    goals = [Goal("person requests served", f"{served} of {len(human)}", "all",
                  served == len(human))]
    delays = list(service_delays(entries, model.starts, t0).values())
    if delays:
        median, worst = float(np.median(delays)), float(max(delays))
        goals += [Goal(f"service start after the model's ({model.name}), median",
                       f"{median:.0f} s", f"≤ {MEDIAN_DELAY_S:.0f} s", median <= MEDIAN_DELAY_S),
                  Goal(f"service start after the model's ({model.name}), worst",
                       f"{worst:.0f} s", f"≤ {WORST_DELAY_S:.0f} s", worst <= WORST_DELAY_S)]
    if searches:
        cut = interruptions(searches, entries)
        whole = [end - start for (_, _, start, end, _, _), ids in zip(searches, cut) if not ids]
        longest = max(whole, default=0.0)
        note = f" ({len(searches) - len(whole)} of {len(searches)} interrupted)" \
            if len(whole) < len(searches) else ""
        goals.append(Goal("longest search not interrupted by another instruction",
                          f"{longest:.0f} s{note}", f"≤ {SEARCH_S:.0f} s", longest <= SEARCH_S))
    own = [e for e in entries if e.instruction.type == ROBOT]
    needless = needless_meetings(own, record.get("recalls", []), t0)
    own = [e for e in own if e not in needless]
    own_served = sum(e.state == "done" for e in own)
    note = f" ({len(needless)} meeting(s) needless: the stranger said who they are)" \
        if needless else ""
    goals.append(Goal("the robot's own instructions served", f"{own_served} of {len(own)}{note}",
                      "all", own_served == len(own)))
    visitors = {r["name"] for r in record.get("registrations", [])}
    residents = {name: value for name, value in people_accuracy(record).items()
                 if name not in visitors}
    if residents:
        name = min(residents, key=residents.get)
        goals.append(Goal("belief accuracy from the run start, lowest resident",
                          f"{residents[name]:.2f} ({name})", f"≥ {BELIEF}",
                          residents[name] >= BELIEF))
    reward = float(sum(e.reward for e in entries if e.state == "done"))
    share = reward / model.reward if model.reward > 0 else float("nan")
    goals.append(Goal(f"run reward / the model's ({model.name})",
                      f"{reward:.3f} / {model.reward:.3f} = {share:.2f}", f"≥ {REWARD_SHARE}",
                      bool(share >= REWARD_SHARE)))
    low = weakest(record.get("activity_counts", {}), categories)
    if low is not None:
        goals.append(Goal("activity recognition in the loop, weakest category",
                          f"{low[1]:.2f} ({low[0]})", f"≥ {ACTIVITY}", low[1] >= ACTIVITY))
    return goals


def goals_markdown(goals):
    """The report's section: each figure beside its goal."""
    lines = ["## Goals", "",
             "Each figure of this run beside its goal (the model: the improved planner on the "
             "same arrivals, `task_planner.problem`'s timing rule; belief accuracy counts from "
             "the run start, an unknown place as wrong).", "",
             "| figure | this run | goal | met |", "|---|---|---|---|"]
    lines += [f"| {g.figure} | {g.value} | {g.goal} | {'yes' if g.met else '**no**'} |"
              for g in goals]
    return lines + [""]
