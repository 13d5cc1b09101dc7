"""Independent re-scoring of the benchmark JSON: every `reward` must follow from the route."""
import json
import subprocess
from pathlib import Path

import pytest

from task_planner.tools import benchmark as bench
from task_planner.graph import load_graph
from task_planner.planner_registry import BENCH_DYNAMIC, BENCH_STATIC, entries, label
from task_planner.reward import load_priorities
from tamp_resources import resource

ROOT = resource()
# the committed figures are documentation of the source checkout, not of the package
CHECKOUT = Path(subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=Path(__file__).parent,
                               capture_output=True, text=True, check=True).stdout.strip())
COMMITTED = CHECKOUT / "docs" / "planner" / "results.json"


def rescore(graph, trial, planner):
    """Walk the route: drive each edge at the given speed, serve the listed instructions in order
    (no earlier than launch), wait where the record says so; sum gamma * beta ** (done - launch)."""
    lengths = {}
    for i, j, length in graph["edges"]:
        lengths[(i, j)] = lengths[(j, i)] = length
    instructions = {i["id"]: i for i in trial["instructions"]}
    waits = dict((position, t) for position, t in planner.get("waits", []))
    at_position = {}
    for instruction_id, position in planner["served"]:
        at_position.setdefault(position, []).append(instruction_id)
    route, clock, total, last_done = planner["route"], 0.0, 0.0, 0.0
    assert route[0] == graph["start_node"]
    for position, node in enumerate(route):
        if position and route[position - 1] != node:  # a repeated node: turned back to it
            clock += lengths[(route[position - 1], node)] / graph["speed_mps"]  # KeyError: no edge
        for instruction_id in at_position.get(position, []):
            instruction = instructions[instruction_id]
            assert instruction["node"] == node
            clock = max(clock, instruction["launch_s"]) + instruction["duration_s"]
            total += instruction["gamma"] * instruction["beta"] ** (clock - instruction["launch_s"])
            last_done = clock
        clock = max(clock, waits.get(position, 0.0))
    served_ids = sorted(i for i, _ in planner["served"])
    assert served_ids == sorted(instructions)
    return total, last_done


def check_document(document):
    graph = document["graph"]
    trials = document["trials"] + document.get("dynamic_trials", [])
    if "named_case" in document:
        trials.append(document["named_case"])
    checked = 0
    for trial in trials:
        for name, planner in trial["planners"].items():
            reward, completion = rescore(graph, trial, planner)
            assert planner["reward"] == pytest.approx(reward, rel=1e-9), name
            assert planner["completion_s"] == pytest.approx(completion, rel=1e-9), name
            assert planner["reward_with_decision"] <= planner["reward"] + 1e-12
            checked += 1
    return checked


def test_fresh_benchmark_json_rescores(tmp_path):
    graph = load_graph(ROOT / "maps" / "household.graph.yaml", cache_dir=tmp_path)
    priorities = list(load_priorities(ROOT / "config" / "priorities.yaml").values())
    config = bench.BenchConfig(static_trials=3, static_count=6, opt_trials=1, dynamic_trials=2,
                               dynamic_count=8, dynamic_mean_gap_s=15.0)
    static, _ = bench.run_static(graph, priorities, config)
    dynamic, _ = bench.run_dynamic(graph, priorities, config)
    path = tmp_path / "run.json"
    path.write_text(json.dumps(bench.json_document(graph, config, static, dynamic)))
    document = json.loads(path.read_text())
    assert set(document["graph"]) == {"nodes", "edges", "speed_mps", "start_node"}
    schema = {"route", "served", "reward", "reward_with_decision", "completion_s", "decision_s"}
    for trial in document["trials"]:
        assert set(trial) == {"instructions", "planners"}
        # a step planner that turned back on an edge also records its waits
        assert all(schema <= set(entry) <= schema | {"waits"}
                   for entry in trial["planners"].values())
    assert "Opt" in document["trials"][0]["planners"]
    assert set(document["trials"][0]["instructions"][0]) == {
        "id", "gamma", "beta", "node", "duration_s", "launch_s", "previous_id"}
    assert check_document(document) == 3 * len(entries(BENCH_STATIC)) + 1 \
        + 2 * len(entries(BENCH_DYNAMIC))
    assert any(w for t in document["dynamic_trials"] for p in t["planners"].values()
               for w in p["waits"])   # idle waits occur and are re-scored
    step = label("seed_step")
    routes = [t["planners"][step]["route"] for t in document["trials"] + document["dynamic_trials"]]
    assert any(a == b for r in routes for a, b in zip(r, r[1:]))  # turns back are re-scored


def test_rescoring_detects_a_wrong_reward(tmp_path):
    graph = load_graph(ROOT / "maps" / "household.graph.yaml", cache_dir=tmp_path)
    priorities = list(load_priorities(ROOT / "config" / "priorities.yaml").values())
    config = bench.BenchConfig(static_trials=1, static_count=4, opt_trials=0)
    document = bench.json_document(graph, config, bench.run_static(graph, priorities, config)[0])
    document["trials"][0]["planners"]["SF"]["reward"] *= 1.001
    with pytest.raises(AssertionError):
        check_document(document)


def test_committed_benchmark_json_rescores():
    assert check_document(json.loads(COMMITTED.read_text())) > 0
