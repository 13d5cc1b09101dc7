"""What a scenario run did, and what the planners' model says it could have earned (ROS-free).

Input: the run record written by `ros_scenario.py` (JSON: requests sent, moves, the robot's
ground-truth trajectory, the start place) and the executor's SQLite journal (read-only). Output:
counts, a timeline, the accumulated-reward curve of the run, and, on the same arrivals (each
instruction's launch time), what FCFS, the seed's planner and the exact optimum earn in the
planners' model (`problem.py`: graph edges at `speed_mps`, service = `duration`, Eq. 4-2), and
what one robot and two earn there under each fleet allocator (`task_planner.fleet`).
"""
import json
import re
import sqlite3
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from perception.activity import load_affordances
from tamp_resources import resource
from task_planner.baselines import PlannerTooLarge
from tamp_bringup.activity_report import activity_markdown
from tamp_bringup.belief_report import (belief_markdown, history_sources, people_accuracy,
                                        place_at, read_searches)
from tamp_bringup.goals_report import goals_markdown, run_goals
from tamp_bringup.time_report import plot_time, robot_shares, time_markdown
from task_planner.exact import SolverTimeout, exact_optimum
from task_planner.fleet import RobotStart, run_fleet
from task_planner.fleet_exact import fleet_exact_optimum
from task_planner.fleet_registry import FLEET_ALLOCATORS, make_allocator
from task_planner.instruction import HUMAN, Instruction, InvalidInstruction
from task_planner.journal_rows import column_problem
from task_planner.metrics import reward_curve
from task_planner.planner_registry import SCENARIO_MODEL, entries, make_planner
from task_planner.problem import Problem, order_to_schedule, schedule_reward
from task_planner.simulate import run_planner
from task_planner.task_buffer import STATE_NAMES

_INSTRUCTION_COLUMNS = ("id", "previous_id", "gamma", "beta", "destination", "type",
                        "start_time", "duration", "source", "target", "status", "function",
                        "destination_name", "text")


@dataclass(frozen=True)
class JournalEntry:
    instruction: Instruction
    state: str              # pending | active | done | failed | cancelled
    received_s: float       # journalled [s]
    started_s: float        # became active (last time) [s]; 0 = never
    completion_s: float     # done/failed/cancelled [s]; 0 = open
    reward: float           # Eq. 4-2 reward earned
    reason: str             # why it failed or was cancelled


def read_journal(path):
    """Every instruction of an executor journal, oldest first, without changing the file.
    Rows the executor quarantines (that do not load: TaskBuffer) are left out."""
    uri = f"file:{Path(path).resolve()}?mode=ro"
    with sqlite3.connect(uri, uri=True) as db:
        rows = db.execute(f"SELECT {', '.join(_INSTRUCTION_COLUMNS)}, state, received_time, "
                          "started_time, completion_time, reward_earned, reason "
                          "FROM instructions ORDER BY seq").fetchall()
    entries = []
    for row in rows:
        if column_problem(row, STATE_NAMES):   # a NULL, text or BLOB of the wrong kind
            continue
        try:
            instruction = Instruction(**dict(zip(_INSTRUCTION_COLUMNS, row[:14])))
        except InvalidInstruction:
            continue
        entries.append(JournalEntry(instruction, STATE_NAMES[row[14]], *row[15:20]))
    return entries


_CLOSED_ELSEWHERE = re.compile(r"^(done|failed|cancelled) by \S+$")   # fleet_link's reasons


def read_fleet_journals(paths):
    """Every instruction of a fleet's journals (each robot's), in the first journal's order and
    then the others', each as journalled by the robot that served (or failed) it: the others
    hold it closed "done by ROBOT", earning nothing, so every reward is counted once; a journal
    that still holds it open (the robot stopped before it learnt) is read last. One path:
    read_journal."""
    merged = {}
    for path in paths:
        for entry in read_journal(path):
            kept = merged.get(entry.instruction.id)
            if kept is None or _standing(entry) > _standing(kept):
                merged[entry.instruction.id] = entry
    return list(merged.values())


def _standing(entry):
    """How much a fleet journal's entry tells: open < closed by another robot < its own."""
    if entry.state in ("pending", "active"):
        return 0
    return 1 if _CLOSED_ELSEWHERE.match(entry.reason) else 2


@dataclass(frozen=True)
class ModelFigures:
    """Accumulated reward of a planner on the run's arrivals, in the planners' model."""

    name: str
    reward: float
    curve: tuple            # (times [s from the scenario start], accumulated reward)
    order: tuple            # instruction ids in service order
    starts: dict = None     # instruction id -> start of its service [s from the scenario start]


def arrivals_problem(graph, entries, speed_mps, start_node, t0, truth=None):
    """The run's instructions as a Problem whose launches are their start times minus `t0`.

    Cancelled instructions are left out (nobody wanted them served); chains to them are cut.
    With `truth` (the record's true places, {name: [[time, place], ...]} on the instructions'
    clock), an instruction for a person is served where the simulator had that person at its
    launch (ground truth, for the model only): the place an instruction names is where the
    robot believed its person, and verbal perception names the welcome hall for someone the
    robot has not met, where nobody is, so the model served such requests back to back there.
    """
    kept = [e.instruction for e in entries if e.state != "cancelled"]
    ids = {i.id for i in kept}

    def true_place(i):
        place = place_at((truth or {}).get(i.target, ()), i.start_time) if i.target else ""
        return graph.index(place) if place in graph.names else i.destination
    shifted = tuple(replace(i, start_time=max(0.0, i.start_time - t0), destination=true_place(i),
                            previous_id=i.previous_id if i.previous_id in ids else 0)
                    for i in kept)
    return Problem(graph, shifted, speed_mps, start_node)


def _figures(name, problem, schedule):
    times, rewards = reward_curve(problem, schedule)
    order = tuple(int(problem.ids[index]) for index, _ in schedule.served)
    starts = {int(problem.ids[index]): float(end) - float(problem.duration[index])
              for (index, _), end in zip(schedule.served, schedule.completion)}
    return ModelFigures(name, schedule_reward(problem, schedule), (tuple(times), tuple(rewards)),
                        order, starts)


MODEL_PLANNERS = tuple((e.name, f"{e.label} (model)") for e in entries(SCENARIO_MODEL))
EXACT_LABEL = "Exact optimum (model, arrivals known)"
GOALS_MODEL = "rollout"   # the model schedule a run's service times are measured against


def model_figures(problem, settings, exact_time_limit_s=60.0):
    """FCFS, the seed's planner and the improved one (online: instructions revealed at their
    launch) and the exact optimum (offline: every launch known in advance, an upper bound)."""
    schedules = {name: run_planner(problem, make_planner(name, settings))
                 for name, _ in MODEL_PLANNERS}
    figures = [_figures(label, problem, schedules[name]) for name, label in MODEL_PLANNERS]
    try:
        order = exact_optimum(problem, int(settings.get("exact_max_instructions", 40)),
                              initial_order=[index for index, _ in schedules["fcfs"].served],
                              time_limit_s=exact_time_limit_s)
        figures.append(_figures(EXACT_LABEL, problem,
                                order_to_schedule(problem, order)))
    except (SolverTimeout, PlannerTooLarge):
        pass  # the report says the optimum is missing
    return figures


FLEET_SIZES = (1, 2)
FLEET_EXACT_MAX = 10          # instructions: the fleet optimum takes seconds up to here
FLEET_EXACT_LIMIT_S = 20.0    # and is given up after this long


def fleet_figures(problem, settings, single_exact=None):
    """{allocator name: {robots: accumulated reward}} on the run's arrivals, every robot starting
    where the run's robot started, and "exact" for the fleet optimum (arrivals known in advance)
    where it finishes within FLEET_EXACT_MAX and FLEET_EXACT_LIMIT_S; `single_exact`: the
    one-robot optimum when it is known already (model_figures')."""
    starts = {k: [RobotStart(problem.start_node)] * k for k in FLEET_SIZES}
    figures = {name: {k: run_fleet(problem, starts[k], make_allocator(name, settings))
                      .reward(problem) for k in FLEET_SIZES} for name in FLEET_ALLOCATORS}
    exact = {} if single_exact is None else {1: single_exact}
    for k in FLEET_SIZES:
        if k in exact:
            continue
        try:
            exact[k] = fleet_exact_optimum(problem, starts[k], FLEET_EXACT_MAX,
                                           FLEET_EXACT_LIMIT_S)[1]
        except (SolverTimeout, PlannerTooLarge):
            continue
    figures["exact"] = exact
    return figures


def fleet_markdown(fleet):
    """The report's section comparing one robot with two on the run's arrivals."""
    lines = ["## One robot or two (model)", "",
             "The same arrivals served by a fleet in the planners' model (`task_planner.fleet`: "
             "each robot drives graph edges at `speed_mps` from the run's start place; a "
             "successor starts after its predecessor, whoever served it), online under each "
             "fleet allocator of `fleet_registry`, and the exact fleet optimum with every launch "
             f"known (`fleet_exact`, up to {FLEET_EXACT_MAX} instructions and "
             f"{FLEET_EXACT_LIMIT_S:.0f} s; one robot: the exact optimum above). Accumulated "
             "reward (Eq. 4-2):", "",
             "| allocator | " + " | ".join(f"{k} robot{'s' if k > 1 else ''}"
                                           for k in FLEET_SIZES) + " |",
             "|---|" + "---|" * len(FLEET_SIZES)]
    for name, rewards in fleet.items():
        cells = [f"{rewards[k]:.3f}" if k in rewards else "not computed" for k in FLEET_SIZES]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines + [""]


def run_curve(entries, t0):
    """Accumulated reward of the run: (completion times [s from t0], running sum), done only."""
    done = sorted((e for e in entries if e.state == "done"), key=lambda e: e.completion_s)
    times = [e.completion_s - t0 for e in done]
    return tuple(times), tuple(np.cumsum([e.reward for e in done]).tolist())


def timeline_rows(entries, t0):
    """One row per instruction: id, source, function text, place, launch, start, done [s from
    t0] (None when it never happened), state, reward, reason."""
    rows = []
    for e in entries:
        i = e.instruction
        rows.append(dict(
            id=i.id, previous_id=i.previous_id, source=i.source, target=i.target,
            function=i.function, gamma=i.gamma, beta=i.beta, place=i.destination_name,
            text=i.text, launch=i.start_time - t0,
            start=e.started_s - t0 if e.started_s > 0 else None,
            end=e.completion_s - t0 if e.completion_s > 0 else None,
            state=e.state, reward=e.reward, reason=e.reason))
    return sorted(rows, key=lambda r: (r["launch"], r["id"]))


def check_order(entries):
    """Problems with the service order: a successor started before its predecessor was done, or
    an instruction started while a higher-priority one was waiting, eligible, at the same place.
    An instruction for a person is served where the robot finds them, which the journal does not
    hold, so only instructions without a target person are compared by place.
    Returns a list of sentences (empty = the order respects chains and priorities)."""
    by_id = {e.instruction.id: e for e in entries}
    problems = []
    for e in entries:
        if e.started_s <= 0:
            continue
        i = e.instruction
        before = by_id.get(i.previous_id)
        if before is not None and not (before.state == "done"
                                       and before.completion_s <= e.started_s):
            problems.append(f"{i.id} started at {e.started_s:.1f} s before its predecessor "
                            f"{before.instruction.id} was done")
        for other in entries:
            o = other.instruction
            waiting = o.start_time <= e.started_s and (other.started_s <= 0
                                                       or other.started_s > e.started_s)
            eligible = o.previous_id == 0 or (o.previous_id in by_id and by_id[
                o.previous_id].state == "done" and by_id[o.previous_id].completion_s
                <= e.started_s)
            same_place = not (o.target or i.target) and o.destination == i.destination
            if (o.id != i.id and waiting and eligible and same_place
                    and o.gamma > i.gamma and other.state not in ("failed", "cancelled")):
                problems.append(f"{i.id} (gamma {i.gamma}) started at {e.started_s:.1f} s while "
                                f"{o.id} (gamma {o.gamma}) waited at the same place")
    return problems


def load_record(path):
    return json.loads(Path(path).read_text())


def summary(entries):
    """Counts: human requests (type HUMAN) served/failed, all instructions per state, reward."""
    human = [e for e in entries if e.instruction.type == HUMAN]
    return dict(requests=len(human), served=sum(e.state == "done" for e in human),
                failed=sum(e.state == "failed" for e in human),
                instructions=len(entries),
                states={name: sum(e.state == name for e in entries) for name in STATE_NAMES},
                reward=float(sum(e.reward for e in entries if e.state == "done")))


def plot_rewards(path, run, figures, title):
    """PNG: the run's accumulated reward (steps at completions) and the model figures."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    for figure, style in zip(figures, ("--", "-.", ":", (0, (5, 1)))):
        times, rewards = figure.curve
        ax.step([0.0, *times], [0.0, *rewards], linestyle=style, where="post",
                label=f"{figure.name}: {figure.reward:.3f}")
    times, rewards = run
    ax.step([0.0, *times], [0.0, *rewards], "-", where="post", color="black", lw=2,
            label=f"this run (simulator): {rewards[-1] if rewards else 0.0:.3f}")
    ax.set_xlabel("time since the scenario start [s, simulated]")
    ax.set_ylabel("accumulated reward (Eq. 4-2)")
    ax.set_title(title)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_trajectory(path, map_path, graph_path, trajectories, title):
    """PNG: the robots' ground-truth trajectories ({robot: [[t, x, y], ...]}, "" for a lone
    robot) over the map and its semantic graph."""
    from floorplan.occupancy_map import load_map
    from floorplan.plotting import plot_map
    from floorplan.semantic_graph import load_graph as load_semantic_graph
    paths = []
    for robot, trajectory in trajectories.items():
        xy = np.asarray([(x, y) for _, x, y in trajectory], dtype=float).reshape(-1, 2)
        if len(xy):
            paths.append((f"{robot or 'robot'} (ground truth)", xy))
    plot_map(load_map(map_path), load_semantic_graph(graph_path), paths=paths, title=title,
             out_path=path)


def _cell(value, digits=1):
    return "-" if value is None else f"{value:.{digits}f}"


def replay_markdown(replay):
    """The report's section on replaying the run's rosbag in rviz (`replay`: the command)."""
    return ["## Replay in rviz", "",
            "The run's rosbag (tf, map, laser, odometry, plans, markers, people, the task "
            "planner's state) replays in rviz with the scenario's view:", "",
            "```bash", "source scripts/env.sh", replay, "```", ""]


def report_markdown(record, entries, figures, run, order_problems, files, sections=(),
                    replay=None, fleet=None):
    """REPORT.md text of one run; sections: lines placed after the counts (the goals, what the
    robot knew of the people, where its time went);
    replay: the command that replays the run's rosbag (None: no section); fleet:
    fleet_figures (None: no section)."""
    t0 = float(record["t0"])
    stats = summary(entries)
    lines = [f"# Scenario `{record['scenario']}`: what happened", "",
             f"Run with `{record['command']}` on {record['date']}: simulator at speed "
             f"{record['speed']} (x real time), executor planner `{record['planner']}`, robot "
             f"starting at `{record['start_place']}`. Simulated time {record['sim_s']:.0f} s, "
             f"wall clock {record['wall_s']:.0f} s"
             + ("." if record["finished"] else "; **the run timed out before every request was "
                                                "closed**."), "",
             "## Counts", "",
             f"- phone requests sent: {len(record['requests'])} "
             f"({sum(r['spoken'] for r in record['requests'])} spoken through the STT node)",
             f"- instructions from people (type human): {stats['requests']}; served "
             f"{stats['served']}, failed {stats['failed']}",
             f"- all instructions in the task buffer: {stats['instructions']} ("
             + ", ".join(f"{k} {v}" for k, v in stats["states"].items() if v) + ")",
             f"- accumulated reward earned (Eq. 4-2 at each completion): {stats['reward']:.3f}",
             "- order: " + ("respects chains (`previous_id`) and, at each place, priorities"
                            if not order_problems else "; ".join(order_problems)), "",
             *(replay_markdown(replay) if replay else ()),
             *sections,
             "## Accumulated reward", "",
             f"![reward]({files['rewards']})", "",
             "The black curve is this run, measured in the simulator (rewards from the "
             "executor's journal). The others are **the planners' model figures** on the same "
             "arrivals (each instruction launched at its recorded launch time and served where "
             "the simulator had its person at the launch, robot starting at the same place): "
             "`task_planner.problem`'s timing rule (graph edges measured by A* "
             "driven at `speed_mps`, service = the instruction's `duration`, nothing else), "
             "computed offline by `tamp_bringup.scenario_report` with `simulate.run_planner` "
             "(FCFS, the seed's planner: online, instructions revealed at their launch) and "
             "`exact.exact_optimum` (offline: it knows every launch in advance, an upper bound). "
             "The simulated robot also turns, accelerates and follows the move_base mock's "
             "paths, so its times differ from the model's.", "",
             "| planner | accumulated reward | service order (instruction ids) |",
             "|---|---|---|"]
    for figure in figures:
        lines.append(f"| {figure.name} | {figure.reward:.3f} | "
                     f"{', '.join(map(str, figure.order))} |")
    if not any(f.name == EXACT_LABEL for f in figures):
        lines.append("| Exact optimum | not computed (time limit or size) | |")
    done_order = [e.instruction.id for e in sorted(
        (e for e in entries if e.state == "done"), key=lambda e: e.completion_s)]
    lines.append(f"| this run (simulator) | {run[1][-1] if run[1] else 0.0:.3f} | "
                 f"{', '.join(map(str, done_order))} |")
    lines += [""] + (fleet_markdown(fleet) if fleet else [])
    model = next((f for f in figures if f.name == dict(MODEL_PLANNERS)[GOALS_MODEL]), None)
    model_starts = model.starts if model is not None else {}
    lines += ["## Timeline", "",
              "Times in seconds of simulated time since the scenario start; launch = when the "
              "person spoke (the instruction's `start_time`), start = robot function began, "
              f"model = the start {dict(MODEL_PLANNERS)[GOALS_MODEL]} gives it on the same "
              "arrivals (the goals' measure), end = done/failed.", "",
              "| id | from | request | place | γ | β | after | launch | start | model | end | "
              "state | reward |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in timeline_rows(entries, t0):
        state = row["state"] + (f" ({row['reason']})" if row["reason"] else "")
        text = row["text"].replace("|", "/")
        lines.append(f"| {row['id']} | {row['source'] or 'robot'} | {text} | {row['place']} | "
                     f"{row['gamma']:g} | {row['beta']:g} | {row['previous_id'] or ''} | "
                     f"{_cell(row['launch'])} | {_cell(row['start'])} | "
                     f"{_cell(model_starts.get(row['id']))} | {_cell(row['end'])} | "
                     f"{state} | {row['reward']:.3f} |")
    lines += ["", "Scripted events (the requests as the phones sent them; the people's moves "
              "are the world file's timed moves, unannounced to the robot):", "",
              "| time [s] | event |", "|---|---|"]
    for event in sorted(record["events"], key=lambda e: e["time"]):
        lines.append(f"| {event['time']:.1f} | {event['what']} |")
    lines += ["", "## Robot trajectory", "", f"![trajectory]({files['trajectory']})", "",
              f"Ground truth (`/base_pose_ground_truth`), {len(record['trajectory'])} samples.",
              ""]
    return "\n".join(lines)


def write_report(record_path, journal_paths, graph, settings, map_path, graph_path, out_dir,
                 exact_time_limit_s=60.0, humans_path=None, replay=None):
    """Write REPORT.md, rewards.png and trajectory.png into `out_dir`; returns the summary.
    journal_paths: the executor's journal, or every robot's of a fleet (read_fleet_journals).
    replay: the command that replays the run's rosbag in rviz, said in the report."""
    record = load_record(record_path)
    entries = read_fleet_journals(journal_paths)
    t0 = float(record["t0"])
    problem = arrivals_problem(graph, entries, float(settings["speed_mps"]),
                               graph.index(record["start_place"]), t0, record.get("truth"))
    figures = model_figures(problem, settings, exact_time_limit_s)
    single = [f.reward for f in figures if f.name == EXACT_LABEL]
    fleet = fleet_figures(problem, settings, single[0] if single else None)
    run = run_curve(entries, t0)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    files = dict(rewards="rewards.png", trajectory="trajectory.png", time="time.png")
    plot_rewards(out_dir / files["rewards"], run, figures, f"Scenario {record['scenario']}")
    plot_trajectory(out_dir / files["trajectory"], map_path, graph_path,
                    record.get("trajectories") or {"": record["trajectory"]},
                    f"Robot trajectory, scenario {record['scenario']}")
    shares = robot_shares(record)
    if shares:
        plot_time(out_dir / files["time"], shares, f"Where the time went, scenario "
                                                   f"{record['scenario']}")
    problems = check_order(entries)
    searches = [s for path in journal_paths for s in read_searches(path)]
    sources = history_sources(humans_path) if humans_path else {}
    model = next(f for f in figures if f.name == dict(MODEL_PLANNERS)[GOALS_MODEL])
    categories = load_affordances(resource("config", "affordances.yaml")).activities
    goals = run_goals(record, entries, searches, model, t0, categories)
    (out_dir / "REPORT.md").write_text(
        report_markdown(record, entries, figures, run, problems, files,
                        goals_markdown(goals)
                        + belief_markdown(record, entries, searches, t0, sources)
                        + activity_markdown(record.get("activity_counts", {}), categories)
                        + time_markdown(shares, files["time"]), replay, fleet))
    return dict(summary(entries), order_problems=problems,
                model={f.name: f.reward for f in figures}, fleet=fleet,
                belief=people_accuracy(record),
                searches=len(searches), sources=sources, replay=replay, time=shares,
                goals=goals)
